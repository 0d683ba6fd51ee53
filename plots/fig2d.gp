# Fig. 2d: training schemes compared: the moving average of the sampled returns over timesteps,
# for this run and every run given with --compare LABEL=DIR (e.g. single-design, no-feedback).
#
# Set by `codesign figures`: plotsdir, datadir, outfile, n_runs, window, label0, label1, ...
# Data: fig2d.dat   t, moving mean; one block per run (index 0 = this run)
load plotsdir.'/style.gp'
set output outfile

set title sprintf('Fig. 2d: training schemes, moving average over %d sampled designs', window)
set xlabel 'timesteps t [thousands of decisions]'
set ylabel 'episode return, moving average'
set key top left
colours = c_best.' '.c_mean.' '.'#2ca02c'.' '.c_other.' '.c_runner.' '.'#9467bd'
plot for [i=0:n_runs-1] datadir.'/fig2d.dat' index i using ($1/1000.0):2 with lines lw 2.2 \
       lc rgb word(colours, (i % 6) + 1) title value(sprintf('label%d', i))
