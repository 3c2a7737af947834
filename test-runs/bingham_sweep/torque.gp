# Torque vs rim shear rate per φ
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot torque.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'torque.png'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'torque T [N m]'
set format y '%.1e'
set xrange [0:*]
set yrange [0:*]
set title "points: measured;  solid: T = T_0 + b γ̇_R (CD §4);  dashed: creeping closed form" font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $5 : NaN) with points pt 7 ps 1.3 lc 1 title 'φ = 0', \
  'torque_lines.csv' every ::1 using 2:(strcol(1) eq 'φ = 0' ? $3 : NaN) with lines lw 2 lc 1 title 'line fit, φ = 0', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $7 : NaN) with lines dt 2 lc 1 title 'creeping closed form'
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'torque.svg'
set xlabel 'rim shear rate γ̇_R [1/s]'
set ylabel 'torque T [N m]'
set format y '%.1e'
set xrange [0:*]
set yrange [0:*]
set title "points: measured;  solid: T = T_0 + b γ̇_R (CD §4);  dashed: creeping closed form" font ',10'
plot 'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $5 : NaN) with points pt 7 ps 1.3 lc 1 title 'φ = 0', \
  'torque_lines.csv' every ::1 using 2:(strcol(1) eq 'φ = 0' ? $3 : NaN) with lines lw 2 lc 1 title 'line fit, φ = 0', \
  'flow_curve.csv' every ::1 using 4:(strcol(1) eq 'φ = 0' ? $7 : NaN) with lines dt 2 lc 1 title 'creeping closed form'
unset output
