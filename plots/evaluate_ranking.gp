# `codesign evaluate`: the designs of a run's state ranked by the test return of its
# deterministic policy, each with its 95 % interval over the plate phases; d* (the state's
# leading design) and the runner-up marked; with `--pressures-of RUN`, also RUN's d*.
#
# Set on the command line (codesign evaluate does it; docs/codesign.md, "Evaluating a run"):
#   datafile   ranking.dat (columns rank, mean_return, ci95, design, role: 0 other, 1 d*, 2 runner-up,
#              3 the d* of the run whose pressures were used)
#   outfile    the PNG to write
#   title      the figure's title
#   plotsdir   the folder of this script (for style.gp)
load plotsdir.'/style.gp'
set output outfile
set title title
set xlabel 'rank by test return (1 = best)'
set ylabel 'test return (max 50), mean ± 95 % interval'
set yrange [*:50]
set offsets 0.5, 0.5, 0, 0
set key top right
# Whether the table marks another run's d* (role 3): its key entry only then.
stats datafile using 5 nooutput
other_title = STATS_max >= 3 ? "other run's d*" : ''
plot datafile using 1:2:3 with yerrorbars pt 7 ps 0.5 lc rgb c_other title 'design', \
     datafile using 1:($5 == 1 ? $2 : NaN):3 with yerrorbars pt 7 ps 1.4 lc rgb c_best title 'd*', \
     datafile using 1:($5 == 2 ? $2 : NaN):3 with yerrorbars pt 5 ps 1.2 lc rgb c_runner title 'runner-up', \
     datafile using 1:($5 == 3 ? $2 : NaN):3 with yerrorbars pt 9 ps 1.4 lc rgb c_dstar title other_title, \
     datafile using 1:($5 == 1 ? $2 : NaN):(sprintf('d* j%d', $4)) with labels left offset 1,1.2 tc rgb c_best notitle, \
     datafile using 1:($5 == 2 ? $2 : NaN):(sprintf('runner-up j%d', $4)) with labels left offset 1,-1.2 tc rgb c_runner notitle, \
     datafile using 1:($5 == 3 ? $2 : NaN):(sprintf("other run's d* j%d", $4)) with labels left offset 1,2.4 tc rgb c_dstar notitle
