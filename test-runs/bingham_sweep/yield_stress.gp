# Yield stress vs φ by four methods, with 95 % intervals
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot yield_stress.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'yield_stress.png'
set xlabel 'volume fraction φ'
set ylabel 'yield stress τ_y [Pa]'
set format y '%.2e'
set xrange [-0.03:0.03]
set xzeroaxis lt -1
set title 'Yield stress by method (bars: 95 % interval; methods offset in φ for legibility)' font ',10'
plot 'yield_stress.csv' every ::1 using ($2 + -0.006):(strcol(3) eq 'bingham_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 5 ps 1.3 lc 1 title 'bingham_intercept' noenhanced, 'yield_stress.csv' every ::1 using ($2 + -0.002):(strcol(3) eq 'casson_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 7 ps 1.3 lc 2 title 'casson_intercept' noenhanced, 'yield_stress.csv' every ::1 using ($2 + 0.002):(strcol(3) eq 'herschel_bulkley' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 9 ps 1.3 lc 3 title 'herschel_bulkley' noenhanced, 'yield_stress.csv' every ::1 using ($2 + 0.006):(strcol(3) eq 'torque_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 11 ps 1.3 lc 4 title 'torque_intercept' noenhanced
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'yield_stress.svg'
set xlabel 'volume fraction φ'
set ylabel 'yield stress τ_y [Pa]'
set format y '%.2e'
set xrange [-0.03:0.03]
set xzeroaxis lt -1
set title 'Yield stress by method (bars: 95 % interval; methods offset in φ for legibility)' font ',10'
plot 'yield_stress.csv' every ::1 using ($2 + -0.006):(strcol(3) eq 'bingham_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 5 ps 1.3 lc 1 title 'bingham_intercept' noenhanced, 'yield_stress.csv' every ::1 using ($2 + -0.002):(strcol(3) eq 'casson_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 7 ps 1.3 lc 2 title 'casson_intercept' noenhanced, 'yield_stress.csv' every ::1 using ($2 + 0.002):(strcol(3) eq 'herschel_bulkley' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 9 ps 1.3 lc 3 title 'herschel_bulkley' noenhanced, 'yield_stress.csv' every ::1 using ($2 + 0.006):(strcol(3) eq 'torque_intercept' ? $4 : NaN):(valid(6) ? $6 : $4):(valid(7) ? $7 : $4) with yerrorbars pt 11 ps 1.3 lc 4 title 'torque_intercept' noenhanced
unset output
