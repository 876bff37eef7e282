/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune: loop tuning tests on an SH-2000TH card (sh2000-tune(1)).
 * The step test: a bounded step of the set-point, gathered on the card
 * every servo cycle (protocol 1.2), reported as rise time, overshoot and
 * settling time to 10 counts, optionally drawn and written as CSV. The
 * axis ends where it started. Auto-tuning (--auto, auto.c): identify the
 * plant, design PID + feed-forward, print, write as asked.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "autotune.h"
#include "tune.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000-tune [-d DEVICE] AXIS --step MM [OPTIONS]\n"
"       sh2000-tune [-d DEVICE] AXIS --auto [--apply] [--save FILE] [--dry-run]\n"
"                   [--bandwidth HZ] [--margin DEG] [--travel MM] [OPTIONS]\n"
"Step test of one axis' servo loop: the set-point steps by MM and holds,\n"
"the card gathers set-point, encoder and DAC every servo cycle, then the\n"
"axis steps back to where it started. Prints rise time (10-90 %%),\n"
"overshoot, settling time to 10 counts, peak following error and DAC.\n"
"\n"
"  -d, --device DEVICE  /dev/sh2000-N, io:0xNNN, sim or sim:NAME\n"
"  --step MM            the step (signed); in one coarse period, so within\n"
"                       the velocity limit times the period\n"
"  --vmax MM/S          velocity bound of the step (default: the axis' vmax)\n"
"  --dac-max CODES      |DAC code| bound during the test (default: the\n"
"                       axis' dac_limit)\n"
"  --ferr-max MM        following-error limit during the test (default\n"
"                       0.1): beyond it the card faults, the test is\n"
"                       aborted and the axis goes back to its start\n"
"  --hold SECONDS       time at the step (default 0.2)\n"
"  --enable             enable the axis for the test (disabled after)\n"
"  --csv FILE           the gathered response as CSV\n"
"  --plot FILE          the response as PNG, or SVG for FILE.svg (gnuplot)\n"
"\n"
"Auto-tuning (--auto): the axis moves (a multisine within --travel, --vmax,\n"
"the axis' amax, --dac-max and --ferr-max, and back to its start), the plant\n"
"is identified from the card's record, PID and feed-forward gains designed;\n"
"prints old and new gains and the predicted margins.\n"
"  --auto               identify and design\n"
"  --bandwidth HZ       the loop's crossover (default: the highest integral\n"
"                       gain the margins allow)\n"
"  --margin DEG         phase margin, 20..89 (default 50); gains predicted\n"
"                       below it are refused\n"
"  --travel MM          the identification stays within the start +- MM\n"
"                       (default 0.1)\n"
"  --apply              write the gains (all or none), then a step test\n"
"                       (--step, default 0.01 mm) with them\n"
"  --save FILE          the gains as a parameter file (sh2000ctl params load)\n"
"  --dry-run            identify (it moves) and design, write nothing\n"
"  --plot, --csv FILE   the step with the new gains (without --apply the\n"
"                       old gains are put back after it)\n"
"  -h, --help           this help\n"
"  -V, --version        versions\n"
"\n"
"Exit status: 0 done, 1 the card or the library failed (or a bound\n"
"refused the step: nothing moved), 2 usage error, 3 device, 4 fault\n"
"latched, 5 aborted on the following-error limit (axis back at its\n"
"start), 6 gnuplot missing or failed; --auto: 1 also when the design is\n"
"refused (nothing written).\n");
}

static int number(const char *opt, const char *v, double lo, double *out)
{
	if (sh2000_tool_double(v, out) < 0 || *out <= lo)
		return sh2000_tool_usage(NULL, "%s: '%s' is not a number above %g",
					 opt, v, lo);
	return 0;
}

/* --auto's options together (after the axis and the common ones). */
static int check_auto(const struct tune_opts *o, int auto_only)
{
	if (!o->autotune)
		return sh2000_tool_usage(NULL, "--%s needs --auto",
					 o->apply ? "apply" : o->save ? "save" :
					 o->dry_run ? "dry-run" :
					 auto_only ? "bandwidth, --margin or --travel" : "auto");
	if (o->dry_run && (o->apply || o->save || o->plot || o->csv))
		return sh2000_tool_usage(NULL, "--dry-run writes nothing: not with --%s",
					 o->apply ? "apply" : o->save ? "save" :
					 o->plot ? "plot" : "csv");
	if (o->margin_deg < 20 || o->margin_deg > 89)
		return sh2000_tool_usage(NULL, "--margin: %g is not a phase margin 20..89 degrees",
					 o->margin_deg);
	if (o->hold_s > 10)
		return sh2000_tool_usage(NULL, "--hold: at most 10 s");
	return 0;
}

static int parse(int argc, char **argv, struct tune_opts *o)
{
	static const struct option lo[] = {
		{ "device", required_argument, NULL, 'd' },
		{ "step", required_argument, NULL, 's' },
		{ "vmax", required_argument, NULL, 'v' },
		{ "dac-max", required_argument, NULL, 'D' },
		{ "ferr-max", required_argument, NULL, 'f' },
		{ "hold", required_argument, NULL, 'H' },
		{ "enable", no_argument, NULL, 'e' },
		{ "csv", required_argument, NULL, 'c' },
		{ "plot", required_argument, NULL, 'p' },
		/* --auto */
		{ "auto", no_argument, NULL, 'A' },
		{ "apply", no_argument, NULL, 'Y' },
		{ "save", required_argument, NULL, 'S' },
		{ "dry-run", no_argument, NULL, 'n' },
		{ "bandwidth", required_argument, NULL, 'B' },
		{ "margin", required_argument, NULL, 'M' },
		{ "travel", required_argument, NULL, 'T' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	int c, r = 0, have_step = 0, ax, auto_only = 0;
	long l;

	memset(o, 0, sizeof(*o));
	o->ferr_max_mm = 0.1;
	o->hold_s = 0.2;
	o->margin_deg = TUNE_DEFAULT_MARGIN;
	o->travel_mm = 0.1;
	opterr = 0;
	while (!r && (c = getopt_long(argc, argv, ":d:hV", lo, NULL)) != -1) {
		switch (c) {
		case 'd': o->device_arg = optarg; break;
		case 's':
			have_step = 1;
			if (sh2000_tool_double(optarg, &o->step_mm) < 0 || o->step_mm == 0)
				r = sh2000_tool_usage(NULL, "--step: '%s' is not a distance other than 0 in mm", optarg);
			break;
		case 'v': r = number("--vmax", optarg, 0, &o->vmax); break;
		case 'f': r = number("--ferr-max", optarg, 0, &o->ferr_max_mm); break;
		case 'H': r = number("--hold", optarg, 0, &o->hold_s); break;
		case 'D':
			if (sh2000_tool_long(optarg, 1, 32767, &l) < 0)
				r = sh2000_tool_usage(NULL, "--dac-max: '%s' is not a DAC code 1..32767", optarg);
			o->dac_max = (int)l;
			break;
		case 'e': o->enable = 1; break;
		case 'c': o->csv = optarg; break;
		case 'p': o->plot = optarg; break;
		/* --auto */
		case 'A': o->autotune = 1; break;
		case 'Y': o->apply = 1; break;
		case 'S': o->save = optarg; break;
		case 'n': o->dry_run = 1; break;
		case 'B': auto_only = 1; r = number("--bandwidth", optarg, 0, &o->bandwidth_hz); break;
		case 'M': auto_only = 1; r = number("--margin", optarg, 0, &o->margin_deg); break;
		case 'T': auto_only = 1; r = number("--travel", optarg, 0, &o->travel_mm); break;
		case 'h': usage(stdout); return -1;
		case 'V': sh2000_tool_print_version(SH2000_TOOLS_VERSION); return -1;
		case ':': r = sh2000_tool_usage(NULL, "option %s needs a value", argv[optind - 1]); break;
		default: r = sh2000_tool_usage(NULL, "unknown option '%s'", argv[optind - 1]); break;
		}
	}
	if (r)
		return r;
	if (optind + 1 != argc)
		return sh2000_tool_usage(NULL, optind < argc ? "one AXIS only" : "which AXIS? (x y z a)");
	ax = sh2000_tool_axis(argv[optind]);
	if (ax < 0)
		return sh2000_tool_usage(NULL, "'%s' is not an axis (x y z a)", argv[optind]);
	o->axis = (unsigned int)ax;
	if (o->autotune || o->apply || o->save || o->dry_run || auto_only)
		return check_auto(o, auto_only);
	if (!have_step)
		return sh2000_tool_usage(NULL, "--step MM or --auto is needed");
	if (o->hold_s > 10)
		return sh2000_tool_usage(NULL, "--hold: at most 10 s");
	return 0;
}

int tune_write_csv(const struct tune_trace *tr, const char *path)
{
	char *text = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&text, &len);
	int r;

	if (!m) {
		sh2000_tool_msg("--csv %s: out of memory", path);
		return SH2000_EXIT_CARD;
	}
	fprintf(m, "time[s],setpoint[counts],encoder[counts],dac[DAC codes]\n");
	for (size_t i = 0; i < tr->n; i++)
		fprintf(m, "%.9g,%.10g,%.10g,%.10g\n", tr->t[i], tr->sp[i],
			tr->enc[i], tr->dac[i]);
	fclose(m);
	r = sh2000_tool_write_text(path, text, len);
	free(text);
	return r;
}

void tune_report(const struct tune_opts *o, const struct tune_trace *tr,
		   const struct tune_metrics *m)
{
	char an = sh2000_tool_axis_name(o->axis);

	printf("axis %c: step %g mm (%.0f counts), held %g s\n", an, o->step_mm,
	       tr->end - tr->start, o->hold_s);
	printf("rise time (10-90 %%)     %.3f ms\n", m->rise_s * 1e3);
	printf("overshoot               %.0f counts (%.1f %%)\n", m->overshoot,
	       m->overshoot_pct);
	if (m->settled)
		printf("settling to %.0f counts   %.3f ms\n", TUNE_SETTLE_COUNTS,
		       m->settle_s * 1e3);
	else
		printf("settling to %.0f counts   not settled within the hold\n",
		       TUNE_SETTLE_COUNTS);
	printf("peak following error    %.1f counts\n", m->peak_ferr);
	printf("peak DAC                %.0f codes\n", m->peak_dac);
}

/* The set-point must be back where it started (tr->start). */
int tune_check_back(struct sh2000 *h, const struct tune_opts *o,
		      const struct tune_trace *tr)
{
	struct sh2000_status st;
	int r = sh2000_poll(h, &st);

	if (r < 0)
		return sh2000_tool_fail(h, r, "status");
	if ((double)st.axis[o->axis].cmd_counts != tr->start) {
		sh2000_tool_msg("%s: axis %c is at %lld counts, not back at %.0f",
				sh2000_device(h), sh2000_tool_axis_name(o->axis),
				(long long)st.axis[o->axis].cmd_counts, tr->start);
		return SH2000_EXIT_CARD;
	}
	printf("back at the start       %.6f mm\n", st.axis[o->axis].cmd_mm);
	return 0;
}

int main(int argc, char **argv)
{
	struct tune_opts o;
	struct tune_trace tr;
	struct tune_metrics m;
	struct sh2000 *h = NULL;
	char title[128];
	int r;

	sh2000_tool_init("sh2000-tune");
	r = parse(argc, argv, &o);
	if (r)
		return r < 0 ? SH2000_EXIT_OK : r;
	if ((r = sh2000_tool_open(&h, o.device_arg)))
		return r;
	if (o.autotune) {
		r = tune_auto(h, &o);
		sh2000_close(h);
		return r;
	}
	r = tune_step(h, &o, &tr);
	if (!r) {
		if (tune_metrics(&tr, &m) < 0)
			sh2000_tool_msg("%s: the encoder never reached 90 %% of the step",
					sh2000_device(h));
		tune_report(&o, &tr, &m);
		r = tune_check_back(h, &o, &tr);
	} else if (r == TUNE_EXIT_ABORTED && tune_check_back(h, &o, &tr)) {
		r = SH2000_EXIT_CARD;
	}
	if (!r && o.csv)
		r = tune_write_csv(&tr, o.csv);
	if (!r && o.plot) {
		snprintf(title, sizeof(title), "%s axis %c: step of %g mm",
			 sh2000_device(h), sh2000_tool_axis_name(o.axis), o.step_mm);
		r = tune_plot(&tr, &m, o.plot, title);
	}
	tune_trace_free(&tr);
	sh2000_close(h);
	return r;
}
