# Normal stress differences vs rim shear rate
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot normal_stress.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'normal_stress.png'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'normal stress difference [Pa]'
set format y '%.2e'
set key outside right
plot 'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $5 : NaN) with linespoints pt 7 lc 1 title 'φ = 0 N1 − N2 (from F)', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $6 : NaN) with points pt 6 ps 1.5 lc 1 title 'φ = 0 N1', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $7 : NaN) with points pt 2 ps 1.5 lc 1 title 'φ = 0 N2', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $5 : NaN) with linespoints pt 7 lc 2 title 'φ = 0.3 N1 − N2 (from F)', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $6 : NaN) with points pt 6 ps 1.5 lc 2 title 'φ = 0.3 N1', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $7 : NaN) with points pt 2 ps 1.5 lc 2 title 'φ = 0.3 N2'
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'normal_stress.svg'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'normal stress difference [Pa]'
set format y '%.2e'
set key outside right
plot 'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $5 : NaN) with linespoints pt 7 lc 1 title 'φ = 0 N1 − N2 (from F)', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $6 : NaN) with points pt 6 ps 1.5 lc 1 title 'φ = 0 N1', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' ? $7 : NaN) with points pt 2 ps 1.5 lc 1 title 'φ = 0 N2', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $5 : NaN) with linespoints pt 7 lc 2 title 'φ = 0.3 N1 − N2 (from F)', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $6 : NaN) with points pt 6 ps 1.5 lc 2 title 'φ = 0.3 N1', \
  'normal_stress.csv' every ::1 using 3:(strcol(1) eq 'φ = 0.3' ? $7 : NaN) with points pt 2 ps 1.5 lc 2 title 'φ = 0.3 N2'
unset output
