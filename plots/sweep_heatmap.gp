# Heat maps of `codesign sweep` for one controller: test return over chamber length l (x) and
# wall thickness w (y), one panel per chamber count, colours on a common 0..50 scale.
#
# Set on the command line (codesign sweep does it; docs/baselines.md shows the command):
#   file_n1, file_n2   heatmap_n1_<controller>.dat, heatmap_n2_<controller>.dat
#                      (columns l_mm w_mm test_return design p1_kPa p2_kPa; one block per l;
#                      NaN for a design the sweep has not reached: left blank)
#   outfile            the PNG to write
#   controller         its name for the titles, e.g. "pid_force"
set terminal pngcairo size 1200,500 noenhanced font 'DejaVu Sans,11'
set encoding utf8
set output outfile
set multiplot layout 1,2 title sprintf('codesign sweep: %s, best test return over the pressure grid (max 50)', controller)
set xlabel 'chamber length l [mm]'
set ylabel 'wall thickness w [mm]'
set xrange [19:41]
set yrange [1.75:4.25]
set xtics 20,2,40
set ytics 2,0.5,4
set cbrange [0:50]
set palette defined (0 '#440154', 12 '#3b528b', 25 '#21918c', 37 '#5ec962', 50 '#fde725')
set tics nomirror
set title 'one chamber (n = 1)'
plot file_n1 using 1:2:3 with image notitle, \
     file_n1 using 1:2:(valid(3) ? sprintf('%.1f', $3) : '') with labels tc rgb '#ffffff' font ',8' notitle
set title 'two chambers (n = 2)'
plot file_n2 using 1:2:3 with image notitle, \
     file_n2 using 1:2:(valid(3) ? sprintf('%.1f', $3) : '') with labels tc rgb '#ffffff' font ',8' notitle
unset multiplot
