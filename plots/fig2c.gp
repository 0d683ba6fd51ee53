# Fig. 2c: reward distributions of the top designs (d* and the runner-up): histograms of the
# returns of their sampled episodes (sampled.csv), each as fractions of that design's samples,
# on common bins.
#
# Set by `codesign figures`: plotsdir, datadir, outfile, n_designs, bin_width, label0, label1, ...
# Data: fig2c_hist.dat      bin low, bin high, bin centre, one fraction column per design
#       fig2c_rewards.dat   the returns themselves, one block per design
load plotsdir.'/style.gp'
set output outfile

set title 'Fig. 2c: reward distributions of the top designs'
set xlabel 'episode return of a sampled design'
set ylabel "fraction of the design's samples"
set key top right
set yrange [0:*]
set offsets 0, 0, graph 0.15, 0   # room for the key above the highest bar
set boxwidth bin_width absolute
colours = c_best.' '.c_runner.' '.c_other
plot for [i=0:n_designs-1] datadir.'/fig2c_hist.dat' using 3:(column(4+i)) with boxes \
       fs transparent solid 0.45 border lc rgb word(colours, i+1) lc rgb word(colours, i+1) \
       title value(sprintf('label%d', i))
