/* SPDX-License-Identifier: MIT */
/*
 * The step response as a picture through gnuplot (Debian's gnuplot-nox):
 * on top the set-point and the encoder in counts from the start with the
 * settling band, below the DAC code; times in ms from the step. The data
 * and the script go to a private temporary directory, removed after
 * (tune_gnuplot_run, for every picture of the tool).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tune.h"

struct step_plot {
	const struct tune_trace *tr;
	const struct tune_metrics *m;
	const char *title;
};

static int write_data(const void *ctx, const char *path)
{
	const struct tune_trace *tr = ((const struct step_plot *)ctx)->tr;
	FILE *f = fopen(path, "w");

	if (!f)
		return -errno;
	for (size_t i = 0; i < tr->n; i++)
		fprintf(f, "%.6f %.1f %.1f %.0f\n", tr->t[i] * 1e3,
			tr->sp[i] - tr->start, tr->enc[i] - tr->start, tr->dac[i]);
	return fclose(f) ? -errno : 0;
}

static int write_script(FILE *f, const void *ctx, const char *out,
			const struct sh2000_tool_plot_kind *k)
{
	const struct step_plot *sp = ctx;
	const struct tune_trace *tr = sp->tr;
	const struct tune_metrics *m = sp->m;
	double step = tr->end - tr->start;
	char settle[32];

	if (m->settled)
		snprintf(settle, sizeof(settle), "%.2f ms", m->settle_s * 1e3);
	else
		snprintf(settle, sizeof(settle), "not settled");
	sh2000_tool_plot_head(f, out, sp->title, k, TUNE_PLOT_W, TUNE_PLOT_H);
	/* the step takes milliseconds of a hold of many: show the step and
	 * a few times its settling */
	fprintf(f, "set xrange [%.3f:%.3f]\n", tr->t[0] * 1e3,
		fmin(tr->t[tr->n - 1], m->settled ? fmax(4 * m->settle_s, 0.01) : INFINITY) * 1e3);
	if (m->settled)
		fprintf(f, "set arrow from %.4f, graph 0 to %.4f, graph 1 nohead dt 3\n",
			m->settle_s * 1e3, m->settle_s * 1e3);
	fprintf(f, "set origin 0,0.35\nset size 1,0.6\n"
		"set title 'rise %.2f ms, overshoot %.0f counts (%.1f %%), settling to %.0f counts: %s'\n"
		"set xlabel 't (ms from the step)'\nset ylabel 'counts from the start'\n"
		"set key bottom right\n"
		"plot DATA using 1:3 with lines lw 2 lc rgb '#d03a1f' title 'encoder', \\\n"
		"     DATA using 1:2 with lines lw 1.5 lc rgb '#1f5fb4' title 'set-point', \\\n"
		"     %.1f with lines dt 2 lc rgb '#777777' title '+-%.0f counts', \\\n"
		"     %.1f with lines dt 2 lc rgb '#777777' notitle\n",
		m->rise_s * 1e3, m->overshoot, m->overshoot_pct, TUNE_SETTLE_COUNTS,
		settle, step + TUNE_SETTLE_COUNTS, TUNE_SETTLE_COUNTS,
		step - TUNE_SETTLE_COUNTS);
	fputs("set origin 0,0\nset size 1,0.35\nunset arrow\n"
	      "set title 'DAC output'\nset ylabel 'DAC code'\n"
	      "plot DATA using 1:4 with lines lc rgb '#2a8a2a' title 'dac'\n"
	      "unset multiplot\n", f);
	return 0;
}

int tune_gnuplot_run(const char *name, const char *out,
		     int (*write_data)(const void *ctx, const char *path),
		     sh2000_tool_plot_script write_script, const void *ctx)
{
	char dir[64], data[96];
	int e, r;

	snprintf(dir, sizeof(dir), "/tmp/sh2000-tune.XXXXXX");
	if (!mkdtemp(dir)) {
		sh2000_tool_msg("--plot: temporary directory: %s", strerror(errno));
		return SH2000_EXIT_CARD;
	}
	snprintf(data, sizeof(data), "%s/%s.dat", dir, name);
	e = write_data(ctx, data);
	if (e) {
		sh2000_tool_msg("--plot %s: %s: %s", out, data, strerror(-e));
		r = SH2000_EXIT_CARD;
	} else {
		r = sh2000_tool_plot(dir, data, out, write_script, ctx);
	}
	unlink(data);
	rmdir(dir);
	return r;
}

int tune_plot(const struct tune_trace *tr, const struct tune_metrics *m,
	      const char *out, const char *title)
{
	struct step_plot sp = { .tr = tr, .m = m, .title = title };

	return tune_gnuplot_run("step", out, write_data, write_script, &sp);
}
