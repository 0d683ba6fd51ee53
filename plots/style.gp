# Common look of the codesign figures, loaded by every plots/fig*.gp.
# PNG through cairo (Debian gnuplot-nox): antialiased lines, UTF-8 text (μ, σ, θ, ±).
# Text is not "enhanced": design labels such as "j21 {1, 28 mm, 2.5 mm}" print as written.
set terminal pngcairo size 1100,650 noenhanced font 'DejaVu Sans,11' linewidth 1.2
set encoding utf8
set grid lc rgb '#e0e0e0' lw 1
set border lc rgb '#404040'
set key opaque box lc rgb '#c0c0c0' samplen 2.5 spacing 1.1
set tics nomirror
# Colours used across the figures
c_best = '#1f77b4'      # blue: best so far, d*
c_mean = '#d62728'      # red: moving average
c_dstar = '#e6a100'     # yellow-orange: d*'s own running mean (the paper's dashed yellow line)
c_runner = '#ff7f0e'    # orange: runner-up
c_other = '#7f7f7f'     # grey: no-feedback / comparison
c_band = '#d9f0d3'      # green tint: the force tolerance band
