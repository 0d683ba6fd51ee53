# Fig. 3: the contact force F over the first evaluation episode (deterministic final policy),
# with the target F_t and the ±tolerance band, and the base angle θ below; for d*, the
# runner-up, and the d* of no-feedback comparison runs.
#
# Set by `codesign figures`: plotsdir, datadir, outfile, n_curves, label0, label1, ...,
#   target_mN, band_lo_mN, band_hi_mN, tolerance_percent, t_max (s)
# Data: fig3.dat   t [s], F [mN], θ [deg]; one block per curve
load plotsdir.'/style.gp'
set terminal pngcairo size 1100,800 noenhanced font 'DejaVu Sans,11' linewidth 1.2
set output outfile
colours = c_best.' '.c_runner.' '.c_other.' '.'#2ca02c'.' '.'#9467bd'
f = datadir.'/fig3.dat'

set multiplot layout 2,1 title 'Fig. 3: force tracking over the first test episode'
set lmargin 10
set rmargin 3
set xrange [0:(t_max > 0 ? t_max : 1)]
set ylabel 'contact force F [mN]'
set format x ''
set key top right
set object 1 rect from graph 0, first band_lo_mN to graph 1, first band_hi_mN fc rgb c_band fs solid 0.8 noborder behind
set yrange [0:*]
set offsets 0, 0, graph 0.3, 0   # room for the key above the band
plot target_mN with lines dt 2 lw 1.5 lc rgb '#2ca02c' title sprintf('F_t = %.3g mN, band ±%.0f %%', target_mN, tolerance_percent), \
     for [i=0:n_curves-1] f index i using 1:2 with lines lw 2.2 lc rgb word(colours, (i % 5) + 1) title value(sprintf('label%d', i))

unset object 1
set format x '%g'
set xlabel 'time t [s]'
set ylabel 'base angle θ [deg]'
set yrange [*:*]
set offsets 0, 0, graph 0.05, graph 0.05
set key off
plot for [i=0:n_curves-1] f index i using 1:3 with lines lw 2.2 lc rgb word(colours, (i % 5) + 1) notitle
unset multiplot
