# Viscosity τ/γ̇ at the rim, corrected (filled) and apparent (open), best fit
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot viscosity.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'viscosity.png'
set logscale xy
set format y '%.1e'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'viscosity η [Pa s]'
set title 'Viscosity curve: τ_R/γ̇_R filled, apparent open, line: best fit (AICc)' font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $13 : NaN) with points pt 7 lc 1 title 'φ = 0 τ_R/γ̇_R', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $12 : NaN) with points pt 6 lc 1 title 'φ = 0 apparent', \
  'fit_curves.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $5 : NaN) with lines lw 2 lc 1 title 'φ = 0 fit: bingham'
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'viscosity.svg'
set logscale xy
set format y '%.1e'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'viscosity η [Pa s]'
set title 'Viscosity curve: τ_R/γ̇_R filled, apparent open, line: best fit (AICc)' font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $13 : NaN) with points pt 7 lc 1 title 'φ = 0 τ_R/γ̇_R', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $12 : NaN) with points pt 6 lc 1 title 'φ = 0 apparent', \
  'fit_curves.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $5 : NaN) with lines lw 2 lc 1 title 'φ = 0 fit: bingham'
unset output
