/* SPDX-License-Identifier: MIT */
/*
 * The pictures of the ramp and chirp tests through gnuplot (plot.c's
 * tune_gnuplot_run over toolcommon's runner): the Bode plot of the measured plant, the loop and
 * the closed loop (magnitude in dB, phase in degrees, log frequency) with
 * the crossover, phase margin, gain margin and bandwidth marked; and the
 * ramp's following error with the set-point's speed.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>

#include "tune.h"

struct bode_plot {
	const struct tune_fr *fr;
	const struct tune_margins *m;
	const char *title;
};

/* Phases of z[0..n) unwrapped along the frequencies, then shifted by
 * whole turns so the last lies in (-360, 0]. */
static void unwrapped(const double complex *z, size_t n, double *ph)
{
	double shift;

	for (size_t i = 0; i < n; i++) {
		ph[i] = carg(z[i]) * 180 / M_PI;
		if (i)
			ph[i] = tune_phase_unwrap(ph[i - 1], ph[i]);
	}
	shift = n ? -360 * ceil(ph[n - 1] / 360) : 0;
	for (size_t i = 0; i < n; i++)
		ph[i] += shift;
}

static int bode_data(const void *ctx, const char *path)
{
	const struct tune_fr *fr = ((const struct bode_plot *)ctx)->fr;
	double pp[TUNE_FR_MAX], pl[TUNE_FR_MAX], pt[TUNE_FR_MAX], pf[TUNE_FR_MAX];
	double complex fb[TUNE_FR_MAX] = { 0 };
	FILE *f = fopen(path, "w");

	if (!f)
		return -errno;
	for (size_t i = 0; i < fr->n; i++)
		fb[i] = fr->loop[i] / (1 + fr->loop[i]);
	unwrapped(fr->plant, fr->n, pp);
	unwrapped(fr->loop, fr->n, pl);
	unwrapped(fr->closed, fr->n, pt);
	unwrapped(fb, fr->n, pf);
	for (size_t i = 0; i < fr->n; i++)
		fprintf(f, "%.6g %.4f %.3f %.4f %.3f %.4f %.3f %.4f %.3f\n", fr->hz[i],
			20 * log10(cabs(fr->plant[i])), pp[i],
			20 * log10(cabs(fr->loop[i])), pl[i],
			20 * log10(cabs(fr->closed[i])), pt[i],
			20 * log10(cabs(fb[i])), pf[i]);
	return fclose(f) ? -errno : 0;
}

/* Frequency ticks at 1, 2 and 5 of every decade in lo..hi: gnuplot's own
 * log ticks mark only the decades, one or two over a typical sweep. */
static void ticks_125(FILE *f, double lo, double hi)
{
	static const double m[] = { 1, 2, 5 };
	const char *sep = "";

	fputs("set xtics (", f);
	for (double d = pow(10, floor(log10(lo))); d <= hi; d *= 10)
		for (unsigned int i = 0; i < 3; i++)
			if (m[i] * d >= lo * (1 - 1e-9) && m[i] * d <= hi * (1 + 1e-9)) {
				fprintf(f, "%s%g", sep, m[i] * d);
				sep = ", ";
			}
	fputs(")\n", f);
}

/* A dashed vertical line at hz with a label at height y (a share of the
 * graph, each mark its own so they never overlap), if hz is known; the
 * label left of the line in the last third of the axis (lo..hi Hz), so it
 * stays inside the graph. */
static void mark(FILE *f, double hz, const char *color, const char *label,
		 double y, double lo, double hi)
{
	int left = log(hz / lo) > 0.66 * log(hi / lo);

	if (isnan(hz))
		return;
	fprintf(f, "set arrow from %g, graph 0 to %g, graph 1 nohead dt 2 lw 1.5 lc rgb '%s'\n",
		hz, hz, color);
	if (label)
		fprintf(f, "set label '%s' at %g, graph %g %s offset %s,0 tc rgb '%s' front\n",
			label, hz, y, left ? "right" : "left", left ? "-0.5" : "0.5", color);
}

static int bode_script(FILE *f, const void *ctx, const char *out,
		       const struct sh2000_tool_plot_kind *k)
{
	const struct bode_plot *bp = ctx;
	const struct tune_margins *m = bp->m;
	double lo = bp->fr->hz[0], hi = bp->fr->hz[bp->fr->n - 1];
	char pm[64], gm[64], bw[64], gml[80];

	snprintf(pm, sizeof(pm), "crossover %.1f Hz, PM %.1f deg", m->wc_hz, m->pm_deg);
	snprintf(gm, sizeof(gm), "-180 deg: GM %.1f dB", m->gm_db);
	snprintf(gml, sizeof(gml), "-180 deg at %+.1f dB: gain may fall %.1f dB",
		 -m->gm_low_db, -m->gm_low_db);
	snprintf(bw, sizeof(bw), "bandwidth %.1f Hz", m->bw_hz);
	sh2000_tool_plot_head(f, out, bp->title, k, TUNE_PLOT_W, TUNE_PLOT_H);
	fprintf(f, "set logscale x\nset xrange [%g:%g]\nset format x '%%g'\n"
		"set key outside right top\nset lmargin 10\nset rmargin 36\n", lo, hi);
	ticks_125(f, lo, hi);
	fprintf(f, "set origin 0,0.48\nset size 1,0.47\n"
		"set title 'magnitude (plant: counts per DAC code)'\nset ylabel 'dB'\n");
	mark(f, m->wc_hz, "#b03060", pm, 0.93, lo, hi);
	mark(f, m->w180_hz, "#6a3d9a", isnan(m->gm_db) ? NULL : gm, 0.85, lo, hi);
	mark(f, m->w180_low_hz, "#777777", isnan(m->gm_low_db) ? NULL : gml, 0.08, lo, hi);
	mark(f, m->bw_hz, "#2a8a2a", bw, 0.77, lo, hi);
	fputs("plot DATA using 1:2 with linespoints pt 7 ps 0.5 lw 2 lc rgb '#1f5fb4' title 'plant P (measured)', \\\n"
	      "     DATA using 1:4 with linespoints pt 7 ps 0.5 lw 2 lc rgb '#d03a1f' title 'loop L = C P', \\\n"
	      "     DATA using 1:8 with lines lw 2 lc rgb '#2a8a2a' title 'feedback L/(1+L)', \\\n"
	      "     DATA using 1:6 with lines lw 1.5 dt 4 lc rgb '#e08000' title 'encoder/set-point (with FF)', \\\n"
	      "     0 with lines lc rgb '#000000' notitle, -3 with lines dt 3 lc rgb '#2a8a2a' title '-3 dB'\n", f);
	fputs("unset label\nunset arrow\nset origin 0,0\nset size 1,0.47\n"
	      "set title 'phase'\nset ylabel 'degrees'\nset xlabel 'frequency (Hz)'\n"
	      "set ytics 45\n", f);
	mark(f, m->wc_hz, "#b03060", NULL, 0, lo, hi);
	mark(f, m->w180_hz, "#6a3d9a", NULL, 0, lo, hi);
	mark(f, m->w180_low_hz, "#777777", NULL, 0, lo, hi);
	mark(f, m->bw_hz, "#2a8a2a", NULL, 0, lo, hi);
	fputs("plot DATA using 1:3 with linespoints pt 7 ps 0.5 lw 2 lc rgb '#1f5fb4' title 'plant P', \\\n"
	      "     DATA using 1:5 with linespoints pt 7 ps 0.5 lw 2 lc rgb '#d03a1f' title 'loop L', \\\n"
	      "     DATA using 1:9 with lines lw 2 lc rgb '#2a8a2a' title 'feedback L/(1+L)', \\\n"
	      "     DATA using 1:7 with lines lw 1.5 dt 4 lc rgb '#e08000' title 'encoder/set-point', \\\n"
	      "     -180 with lines lc rgb '#000000' title '-180 deg'\n"
	      "unset multiplot\n", f);
	return 0;
}

int tune_plot_bode(const struct tune_fr *fr, const struct tune_margins *m,
		   const char *out, const char *title)
{
	struct bode_plot bp = { .fr = fr, .m = m, .title = title };

	return tune_gnuplot_run("bode", out, bode_data, bode_script, &bp);
}

struct ramp_plot {
	const struct tune_ramp *rp;
	const char *title;
};

static int ramp_data(const void *ctx, const char *path)
{
	const struct tune_ramp *rp = ((const struct ramp_plot *)ctx)->rp;
	FILE *f = fopen(path, "w");
	double um = 1e3 / rp->counts_per_mm;

	if (!f)
		return -errno;
	for (size_t i = 1; i + 1 < rp->n; i++) {
		double ts = rp->t[i + 1] - rp->t[i - 1];

		fprintf(f, "%.6f %.5f %.3f %d\n", rp->t[i] * 1e3, rp->ferr[i] * um,
			(rp->sp[i + 1] - rp->sp[i - 1]) / ts / rp->counts_per_mm,
			rp->cruise[i]);
	}
	return fclose(f) ? -errno : 0;
}

static int ramp_script(FILE *f, const void *ctx, const char *out,
		       const struct sh2000_tool_plot_kind *k)
{
	const struct ramp_plot *p = ctx;
	const struct tune_ramp *rp = p->rp;
	double um = 1e3 / rp->counts_per_mm;

	sh2000_tool_plot_head(f, out, p->title, k, TUNE_PLOT_W, TUNE_PLOT_H);
	fprintf(f, "set autoscale xfix\nset origin 0,0.35\nset size 1,0.6\n"
		"set title 'following error: constant speed peak %.3f um, RMS %.3f um; accelerating peak %.3f um'\n"
		"set ylabel 'following error (um)'\nset xlabel 't (ms from the start)'\n"
		"set key bottom right\n"
		"plot DATA using 1:2 with lines lw 1.5 lc rgb '#d03a1f' title 'following error', \\\n"
		"     DATA using 1:($4 > 0 ? $2 : 1/0) with points pt 7 ps 0.3 lc rgb '#1f5fb4' title 'at constant speed'\n",
		rp->cruise_peak * um, rp->cruise_rms * um, rp->accel_peak * um);
	fputs("set origin 0,0\nset size 1,0.35\nset title 'set-point speed'\n"
	      "set ylabel 'mm/s'\n"
	      "plot DATA using 1:3 with lines lc rgb '#2a8a2a' title 'set-point speed'\n"
	      "unset multiplot\n", f);
	return 0;
}

int tune_plot_ramp(const struct tune_ramp *rp, const char *out,
		   const char *title)
{
	struct ramp_plot p = { .rp = rp, .title = title };

	return tune_gnuplot_run("ramp", out, ramp_data, ramp_script, &p);
}
