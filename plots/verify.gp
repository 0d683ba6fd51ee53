# `codesign verify`: each subject's return under each held-out condition, mean ± 95 % interval
# over the plate phases, subjects side by side within a condition.
#
# Set on the command line (codesign verify does it; docs/verify.md):
#   datafile    verify.dat: a block per subject (gnuplot index), rows: condition index, mean, ci95
#   subjects    the subjects' names, space-separated, in block order
#   conditions  the conditions' names, space-separated, in index order, % doubled (tic labels
#               are format strings)
#   outfile     the PNG to write
#   title       the figure's title
#   plotsdir    the folder of this script (for style.gp)
load plotsdir.'/style.gp'
set output outfile
set title title
set ylabel 'return (max 50), mean ± 95 % interval'
set yrange [*:50]
n = words(subjects)
m = words(conditions)
set xrange [-0.5:m - 0.5]
set xtics () rotate by -25
do for [k = 1:m] { set xtics add (word(conditions, k) k - 1) }
set key outside right top
width = 0.7
dx(i) = n > 1 ? -width / 2 + width * (i - 1) / (n - 1) : 0
plot for [i = 1:n] datafile index (i - 1) using ($1 + dx(i)):2:3 with yerrorbars pt 7 ps 0.8 title word(subjects, i)
