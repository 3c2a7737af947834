# Rim stress: plate-corrected τ_R (filled) and apparent τ_app = 2T/(πR³) (open), best fit by AICc
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot stress.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'stress.png'
set logscale xy
set format y '%.1e'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'rim shear stress [Pa]'
set title 'Flow curve: τ_R = T/(2πR³)(3 + d ln T/d ln γ̇_R) filled, apparent open, line: best fit (AICc)' font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $11 : NaN) with points pt 7 lc 1 title 'φ = 0 τ_R', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $10 : NaN) with points pt 6 lc 1 title 'φ = 0 τ_{app}', \
  'fit_curves.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $4 : NaN) with lines lw 2 lc 1 title 'φ = 0 fit: bingham'
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'stress.svg'
set logscale xy
set format y '%.1e'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'rim shear stress [Pa]'
set title 'Flow curve: τ_R = T/(2πR³)(3 + d ln T/d ln γ̇_R) filled, apparent open, line: best fit (AICc)' font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $11 : NaN) with points pt 7 lc 1 title 'φ = 0 τ_R', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $10 : NaN) with points pt 6 lc 1 title 'φ = 0 τ_{app}', \
  'fit_curves.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $4 : NaN) with lines lw 2 lc 1 title 'φ = 0 fit: bingham'
unset output
