# Fig. 2b: the continuous part of d*'s design distribution, q_cont(p | j*), after each update:
# μ1 (the median pressure of chamber 1, map of the latent mean) with the band μ1 ± σ1, and σ1
# (delta-method standard deviation), in kPa; for a two-chamber d* also μ2 and σ2. The final p*
# is the dash-dotted line. A value shown at update k holds until update k + 1 (steps, bands of width 1). Before d*'s first sample nothing is drawn; between samples the values
# are carried forward (q_cont of a design changes only when that design is sampled).
#
# Set by `codesign figures`: plotsdir, datadir, outfile, chambers (1 or 2), p_star1, p_star2,
#   k_transition, k_exploitation (first update in that phase, -1: none), k_end (last update),
#   dstar_label
# Data: fig2b.dat   k, t, mu1, sigma1, mu2, sigma2   (kPa)
load plotsdir.'/style.gp'
set output outfile

set title 'Fig. 2b: q_cont of '.dstar_label
set xlabel 'update k (one per iteration of Algorithm 1)'
set ylabel 'pressure [kPa]'
set key top right
set yrange [0:*]
set xrange [0:k_end + 1]
if (k_transition >= 0) {
  set arrow 1 from first k_transition, graph 0 to first k_transition, graph 1 nohead dt 2 lc rgb '#606060'
  set label 1 ' transition' at first k_transition, graph 0.04 left tc rgb '#606060'
}
if (k_exploitation >= 0) {
  set arrow 2 from first k_exploitation, graph 0 to first k_exploitation, graph 1 nohead dt 2 lc rgb '#606060'
  set label 2 ' exploitation' at first k_exploitation, graph 0.04 left tc rgb '#606060'
}

f = datadir.'/fig2b.dat'
if (chambers == 2) {
  plot f using ($1+0.5):3:(0.5):4 with boxxyerror fc rgb c_best fs transparent solid 0.15 noborder title 'μ1 ± σ1', \
       f using ($1+0.5):5:(0.5):6 with boxxyerror fc rgb c_runner fs transparent solid 0.15 noborder title 'μ2 ± σ2', \
       f using 1:3 with steps lw 2.2 lc rgb c_best title 'μ1', \
       f using 1:4 with steps lw 1.6 dt 3 lc rgb c_best title 'σ1', \
       f using 1:5 with steps lw 2.2 lc rgb c_runner title 'μ2', \
       f using 1:6 with steps lw 1.6 dt 3 lc rgb c_runner title 'σ2', \
       p_star1 with lines dt 4 lw 1.5 lc rgb '#202020' title sprintf('p*1 = %.3g kPa', p_star1), \
       p_star2 with lines dt 5 lw 1.5 lc rgb '#606060' title sprintf('p*2 = %.3g kPa', p_star2)
} else {
  plot f using ($1+0.5):3:(0.5):4 with boxxyerror fc rgb c_best fs transparent solid 0.15 noborder title 'μ1 ± σ1', \
       f using 1:3 with steps lw 2.2 lc rgb c_best title 'μ1', \
       f using 1:4 with steps lw 1.6 dt 3 lc rgb c_mean title 'σ1', \
       p_star1 with lines dt 4 lw 1.5 lc rgb '#202020' title sprintf('p*1 = %.3g kPa', p_star1)
}
