# Relative residuals of every fitted model
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot residuals.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1400,650 font 'DejaVu Sans,10'
set output 'residuals.png'
set multiplot layout 2,4 title 'Relative residuals (τ_{model} − τ_R)/τ_R of each model, in %' font ',11'
set logscale x
set key off
set xlabel 'γ̇_R [1/s]'
set ylabel 'residual [%]'
set xzeroaxis lt -1
set title 'bingham' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'carreau' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'carreau' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'casson' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'casson' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'cross' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'cross' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'herschel_bulkley' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'herschel_bulkley' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'newtonian' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'newtonian' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'power_law' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'power_law' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'series'
unset border
unset tics
unset xlabel
unset ylabel
unset grid
unset xzeroaxis
set key center center
set yrange [0:1]
plot NaN with linespoints pt 7 lc 1 title 'φ = 0'
unset multiplot
set terminal svg size 1400,650 dynamic font 'DejaVu Sans,10'
set output 'residuals.svg'
set multiplot layout 2,4 title 'Relative residuals (τ_{model} − τ_R)/τ_R of each model, in %' font ',11'
set logscale x
set key off
set xlabel 'γ̇_R [1/s]'
set ylabel 'residual [%]'
set xzeroaxis lt -1
set title 'bingham' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'bingham' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'carreau' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'carreau' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'casson' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'casson' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'cross' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'cross' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'herschel_bulkley' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'herschel_bulkley' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'newtonian' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'newtonian' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'power_law' noenhanced
plot 'residuals.csv' every ::1 using 3:(strcol(1) eq 'φ = 0' && strcol(2) eq 'power_law' ? $4 : NaN) with linespoints pt 7 lc 1 title 'φ = 0'
set title 'series'
unset border
unset tics
unset xlabel
unset ylabel
unset grid
unset xzeroaxis
set key center center
set yrange [0:1]
plot NaN with linespoints pt 7 lc 1 title 'φ = 0'
unset multiplot
unset output
