/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune: loop tuning tests on an SH-2000TH card (sh2000-tune(1)).
 * The step test: a bounded step of the set-point, gathered on the card
 * every servo cycle (protocol 1.2), reported as rise time, overshoot and
 * settling time to 10 counts, optionally drawn and written as CSV; the
 * ramp and chirp tests (testruns.c). The axis ends where it started.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tune.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000-tune [-d DEVICE] AXIS --step MM | --ramp MM/S | --chirp F0:F1\n"
"                   [OPTIONS]\n"
"Tests of one axis' servo loop, gathered on the card every servo cycle;\n"
"the axis ends where it started.\n"
"  step:  the set-point steps by MM and holds, then steps back. Prints rise\n"
"         time (10-90 %%), overshoot, settling time to 10 counts, peak\n"
"         following error and DAC.\n"
"  ramp:  the set-point moves TRAVEL at MM/S (accelerating at the axis'\n"
"         amax) and back. Prints the following error at constant speed\n"
"         (peak, RMS) and while accelerating.\n"
"  chirp: a logarithmic swept sine F0..F1 Hz around the start. Prints the\n"
"         gain and phase margins, crossover and closed-loop bandwidth from\n"
"         the measured plant and the card's PID.\n"
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
"  --ramp MM/S          the ramp's speed (signed: its direction)\n"
"  --chirp F0:F1        the sweep's frequencies, Hz (F0 < F1)\n"
"  --travel MM          the window the test stays in, from the start\n"
"                       (ramp: its length, default enough to hold the\n"
"                       speed 50 ms; chirp: default 1)\n"
"  --amplitude MM       the sweep's amplitude (default 0.002)\n"
"  --duration SECONDS   the sweep's length (default 0.8)\n"
"  --accel MM/S^2       the sweep's acceleration bound: above the frequency\n"
"                       where the amplitude would need more, it falls as\n"
"                       1/f^2 (default: what takes half the DAC bound\n"
"                       through the axis' kaff; without kaff its amax)\n"
"  --enable             enable the axis for the test (disabled after)\n"
"  --csv FILE           the gathered response (chirp: the frequency\n"
"                       response) as CSV\n"
"  --plot FILE          the response (chirp: the Bode plot) as PNG, or SVG\n"
"                       for FILE.svg (gnuplot)\n"
"  -h, --help           this help\n"
"  -V, --version        versions\n"
"\n"
"Exit status: 0 done, 1 the card or the library failed (or a bound\n"
"refused the step: nothing moved), 2 usage error, 3 device, 4 fault\n"
"latched, 5 aborted on the following-error limit (axis back at its\n"
"start), 6 gnuplot missing or failed.\n");
}

static int number(const char *opt, const char *v, double lo, double *out)
{
	if (sh2000_tool_double(v, out) < 0 || *out <= lo)
		return sh2000_tool_usage(NULL, "%s: '%s' is not a number above %g",
					 opt, v, lo);
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
		/* ramp and chirp tests */
		{ "ramp", required_argument, NULL, 'r' },
		{ "chirp", required_argument, NULL, 'C' },
		{ "travel", required_argument, NULL, 't' },
		{ "amplitude", required_argument, NULL, 'A' },
		{ "duration", required_argument, NULL, 'u' },
		{ "accel", required_argument, NULL, 'a' },
		{ "enable", no_argument, NULL, 'e' },
		{ "csv", required_argument, NULL, 'c' },
		{ "plot", required_argument, NULL, 'p' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	int c, r = 0, tests = 0, ax;
	long l;

	memset(o, 0, sizeof(*o));
	o->ferr_max_mm = 0.1;
	o->hold_s = 0.2;
	o->amplitude_mm = TUNE_CHIRP_AMPLITUDE;
	o->duration_s = TUNE_CHIRP_DURATION;
	opterr = 0;
	while (!r && (c = getopt_long(argc, argv, ":d:hV", lo, NULL)) != -1) {
		switch (c) {
		case 'd': o->device_arg = optarg; break;
		case 's':
			tests++;
			o->test = TUNE_TEST_STEP;
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
		case 'r': case 'C': case 't': case 'A': case 'a': case 'u':
			r = tune_parse_option(c, optarg, o);
			tests += c == 'r' || c == 'C';
			break;
		case 'e': o->enable = 1; break;
		case 'c': o->csv = optarg; break;
		case 'p': o->plot = optarg; break;
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
	if (tests != 1)
		return sh2000_tool_usage(NULL, tests ? "one test at a time: --step, --ramp or --chirp" :
					 "which test? --step MM, --ramp MM/S or --chirp F0:F1");
	if (o->hold_s > 10)
		return sh2000_tool_usage(NULL, "--hold: at most 10 s");
	return tune_check_options(o);
}

static void step_csv(FILE *m, const void *ctx)
{
	const struct tune_trace *tr = ctx;

	fprintf(m, "time[s],setpoint[counts],encoder[counts],dac[DAC codes]\n");
	for (size_t i = 0; i < tr->n; i++)
		fprintf(m, "%.9g,%.10g,%.10g,%.10g\n", tr->t[i], tr->sp[i],
			tr->enc[i], tr->dac[i]);
}

static void report(const struct tune_opts *o, const struct tune_trace *tr,
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
	/* ramp and chirp tests */
	if (o.test != TUNE_TEST_STEP) {
		r = o.test == TUNE_TEST_RAMP ? tune_run_ramp(h, &o) : tune_run_chirp(h, &o);
		sh2000_close(h);
		return r;
	}
	r = tune_step(h, &o, &tr);
	if (!r) {
		if (tune_metrics(&tr, &m) < 0)
			sh2000_tool_msg("%s: the encoder never reached 90 %% of the step",
					sh2000_device(h));
		report(&o, &tr, &m);
		r = tune_check_back(h, o.axis, tr.start);
	} else if (r == TUNE_EXIT_ABORTED && tune_check_back(h, o.axis, tr.start)) {
		r = SH2000_EXIT_CARD;
	}
	if (!r && o.csv)
		r = tune_write_csv(o.csv, step_csv, &tr);
	if (!r && o.plot) {
		snprintf(title, sizeof(title), "%s axis %c: step of %g mm",
			 sh2000_device(h), sh2000_tool_axis_name(o.axis), o.step_mm);
		r = tune_plot(&tr, &m, o.plot, title);
	}
	tune_trace_free(&tr);
	sh2000_close(h);
	return r;
}
