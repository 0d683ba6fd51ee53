# Fig. 2a: the return of every sampled design over timesteps, the moving average over the last
# `window` samples (red), the best return so far (blue), the gap between them shaded, the running
# mean of d*'s own samples (dashed yellow), and the phases of Algorithm 2.
#
# Set by `codesign figures` (see RUN/figures/gnuplot_commands.txt for the exact command):
#   plotsdir, datadir, outfile      folders and the PNG to write
#   run_label                       e.g. "co-design"
#   t_end                           last timestep of the run
#   t_transition, t_exploitation    start of those phases in timesteps (-1: not reached / none)
#   window, dstar_label, dstar_samples (0: d* never sampled; its file then holds no points)
# Data (RUN/figures/data/):
#   fig2a_samples.dat   t, k, j, return                      (one row per sampled design)
#   fig2a_curves.dat    t, moving mean, best so far          (after each update's last sample)
#   fig2a_dstar.dat     t, running mean of d*'s samples      (after each update that sampled d*)
load plotsdir.'/style.gp'
set output outfile

set title sprintf('Fig. 2a (%s): return of every sampled design', run_label)
set xlabel 'timesteps t [thousands of decisions]'
set ylabel 'episode return (sum of rewards, max 50)'
set xrange [0:t_end/1000.0]
set key top left

# Phases: boundaries as dashed lines, names at the bottom.
e1 = t_transition >= 0 ? t_transition : (t_exploitation >= 0 ? t_exploitation : t_end)
if (t_transition >= 0 || t_exploitation >= 0) {
  set label 1 'exploration' at first e1/2000.0, graph 0.04 center tc rgb '#606060'
}
if (t_transition >= 0) {
  set arrow 1 from first t_transition/1000.0, graph 0 to first t_transition/1000.0, graph 1 nohead dt 2 lc rgb '#606060'
  e2 = t_exploitation >= 0 ? t_exploitation : t_end
  set label 2 'transition' at first (t_transition + e2)/2000.0, graph 0.04 center tc rgb '#606060'
}
if (t_exploitation >= 0) {
  set arrow 2 from first t_exploitation/1000.0, graph 0 to first t_exploitation/1000.0, graph 1 nohead dt 2 lc rgb '#606060'
  set label 3 'exploitation' at first (t_exploitation + t_end)/2000.0, graph 0.04 center tc rgb '#606060'
}

samples = datadir.'/fig2a_samples.dat'
curves = datadir.'/fig2a_curves.dat'
dstar = datadir.'/fig2a_dstar.dat'
plot curves using ($1/1000.0):2:3 with filledcurves fc rgb '#dbe7f3' fs solid 0.6 noborder title 'gap: best so far − moving average', \
     samples using ($1/1000.0):4 with points pt 7 ps 0.35 lc rgb '#60707070' title 'sampled design (first episode)', \
     curves using ($1/1000.0):2 with lines lw 2.2 lc rgb c_mean title sprintf('moving average (%d samples)', window), \
     curves using ($1/1000.0):3 with lines lw 2.2 lc rgb c_best title 'best so far', \
     dstar using ($1/1000.0):2 with lines dt 2 lw 2.2 lc rgb c_dstar title dstar_label.' running mean'
