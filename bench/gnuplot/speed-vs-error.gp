# speed-vs-error.gp - one speed-against-error plot from bench_speed_vs_error's data files:
# a line per N sweep (series-*.dat, N labelled along the first), dashed for the progressive
# series (K accumulated frames; bench_speed_vs_error writes them after the N sweeps, from
# series number `first_progressive` on), the N = 40 axis variants as points (axes.dat), and
# split-sum, which takes no samples, as one labelled star (splitsum.dat, bench/sweep_fronts.py).
# softlight-gl is not plotted: its time is wall time, not CPU time (docs/accuracy.md has it in a
# table). Log-log: both cost and error span decades.
# bench/speed-vs-error.sh calls it once per plot:
#   gnuplot -e "dir='out/speed-vs-error'; out='docs/accuracy/speed-vs-error.png'; col=3; \
#               ylab='nRMSE, total'" bench/gnuplot/speed-vs-error.gp
# col: 3 nRMSE total, 4 nRMSE specular, 5 mean relative error, 6 share > 8/255, 7 p99 relative.
load dir.'/series.gp'
set terminal pngcairo size 960,620 font ",10"
set output out
set logscale xy
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set xlabel 'lighting CPU ms per frame, summed over threads (error size, median; lower is faster)'
set ylabel ylab.' (against ground truth; lower is better)'
set key outside right top box opaque font ",9"
set title 'speed against error, mean over the shipped scenes'
dash(i) = i >= first_progressive ? 2 : 1
plot for [i=1:nseries] sprintf('%s/series-%d.dat', dir, i) using 2:col with linespoints pt 7 ps 0.8 lw 1.5 \
         dt dash(i) title columnheader(2), \
     sprintf('%s/series-1.dat', dir) using 2:col:(sprintf('%d', $1)) with labels offset 0,-0.9 font ",7" notitle, \
     dir.'/axes.dat' using 2:col with points pt 4 ps 1.0 lc rgb '#777777' title 'single points (N = 40 axes, K env lights)', \
     dir.'/splitsum.dat' using 2:col with points pt 3 ps 2.0 lw 2 lc rgb '#000000' title 'split-sum (no samples)', \
     dir.'/splitsum.dat' using 2:col:(' split-sum') with labels left offset 1,0 font ",8" notitle
