# Relative viscosity against the classic correlations
# Data: the CSV files beside this script (written by rheosim from summary.json).
# Regenerate: gnuplot relative_viscosity.gp
set datafile separator ','
set datafile missing 'nan'
set grid
set key outside right top
set encoding utf8
set terminal pngcairo size 1000,600 font 'DejaVu Sans,10'
set output 'relative_viscosity.png'
set xlabel 'volume fraction φ'
set ylabel 'relative viscosity η_r'
set logscale y
set xrange [0:*]
set yrange [0.9:*]
set key inside left top
set title 'Relative viscosity: no finished point with φ > 0, curves use φ_m = 0.63 (not fitted)' font ',10'
plot 'relative_viscosity.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $3 : NaN):4 with yerrorbars pt 7 ps 1.3 lc 1 title 'η_r measured', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $3 : NaN) with lines lw 2 lc rgb '#555555' dt 3 title 'Einstein 1 + 2.5φ', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $4 : NaN) with lines lw 2 lc rgb '#1b9e77' dt 2 title 'Batchelor 1 + 2.5φ + 6.2φ²', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $5 : NaN) with lines lw 2 lc rgb '#d95f02' title 'Krieger–Dougherty', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $6 : NaN) with lines lw 2 lc rgb '#7570b3' dt 4 title 'Maron–Pierce', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $7 : NaN) with lines lw 3 lc rgb '#e7298a' title 'measured: Boyer et al. 2011', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $8 : NaN) with lines lw 3 lc rgb '#66a61e' dt 5 title 'measured: Zarraga et al. 2000'
set terminal svg size 1000,600 dynamic font 'DejaVu Sans,10'
set output 'relative_viscosity.svg'
set xlabel 'volume fraction φ'
set ylabel 'relative viscosity η_r'
set logscale y
set xrange [0:*]
set yrange [0.9:*]
set key inside left top
set title 'Relative viscosity: no finished point with φ > 0, curves use φ_m = 0.63 (not fitted)' font ',10'
plot 'relative_viscosity.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $3 : NaN):4 with yerrorbars pt 7 ps 1.3 lc 1 title 'η_r measured', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $3 : NaN) with lines lw 2 lc rgb '#555555' dt 3 title 'Einstein 1 + 2.5φ', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $4 : NaN) with lines lw 2 lc rgb '#1b9e77' dt 2 title 'Batchelor 1 + 2.5φ + 6.2φ²', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $5 : NaN) with lines lw 2 lc rgb '#d95f02' title 'Krieger–Dougherty', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $6 : NaN) with lines lw 2 lc rgb '#7570b3' dt 4 title 'Maron–Pierce', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $7 : NaN) with lines lw 3 lc rgb '#e7298a' title 'measured: Boyer et al. 2011', 'relative_viscosity_curves.csv' every ::1 using 2:(strcol(1) eq 'fluid' ? $8 : NaN) with lines lw 3 lc rgb '#66a61e' dt 5 title 'measured: Zarraga et al. 2000'
unset output
