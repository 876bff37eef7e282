/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune: loop tuning tests on an SH-2000TH card (sh2000-tune(1)).
 * The step test: a bounded step of the set-point, gathered on the card
 * every servo cycle (protocol 1.2), reported as rise time, overshoot and
 * settling time to 10 counts, optionally drawn and written as CSV; the
 * ramp and chirp tests (testruns.c). The axis ends where it started.
 * Auto-tuning (--auto, auto.c): identify the plant, design PID +
 * feed-forward, print, write as asked.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "autotune.h"
#include "tune.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000-tune [-d DEVICE] AXIS --step MM | --ramp MM/S | --chirp F0:F1\n"
"                   [OPTIONS]\n"
"       sh2000-tune [-d DEVICE] AXIS --auto [--apply] [--save FILE] [--dry-run]\n"
"                   [--bandwidth HZ] [--margin DEG] [--gain-margin DB]\n"
"                   [--travel MM] [OPTIONS]\n"
"       sh2000-tune [-d DEVICE] AXIS --gantry [--ramp MM/S] [OPTIONS]\n"
"       sh2000-tune [-d DEVICE] AXIS --gantry --auto [--apply | --dry-run]\n"
"                   [--gain-margin DB] [--ramp MM/S] [OPTIONS]\n"
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
"  --vmax MM/S          velocity bound of every test (default: the axis'\n"
"                       vmax)\n"
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
"  --enable             enable the axis for the test (disabled after);\n"
"                       implied on the in-process `sim` card\n"
"  --csv FILE           the gathered response (chirp: the frequency\n"
"                       response) as CSV\n"
"  --plot FILE          the response (chirp: the Bode plot) as PNG, or SVG\n"
"                       for FILE.svg (gnuplot)\n"
"\n"
"Auto-tuning (--auto): the axis moves (a multisine within --travel, --vmax,\n"
"the axis' amax, --dac-max and --ferr-max, and back to its start), the plant\n"
"is identified from the card's record, PID and feed-forward gains designed;\n"
"prints old and new gains and the predicted margins.\n"
"  --auto               identify and design\n"
"  --bandwidth HZ       the loop's crossover (default: the highest integral\n"
"                       gain the margins allow)\n"
"  --margin DEG         phase margin, 20..89 (default 45.5); gains\n"
"                       predicted below it are refused\n"
"  --gain-margin DB     the least gain margin, 3..30 (default 8)\n"
"  --travel MM          the identification stays within the start +- MM\n"
"                       (default 0.1)\n"
"  --apply              write the gains (all or none), then a step test\n"
"                       (--step, default 0.01 mm) with them\n"
"  --save FILE          the gains as a parameter file (sh2000ctl params load)\n"
"  --dry-run            identify (it moves) and design, write nothing\n"
"  --plot, --csv FILE   the step with the new gains (without --apply the\n"
"                       old gains are put back after it); --plot also\n"
"                       sweeps a chirp with them and draws its Bode plot\n"
"                       to FILE-bode.png (or .svg), and prints the\n"
"                       measured margins beside the predicted ones\n"
"\n"
"Gantry pairs (--gantry, protocol 1.7): AXIS is a side of the card's\n"
"gantry pair; both sides ramp together (--ramp, default 100 mm/s, --travel)\n"
"twice, with the card's coupling gains and with none (put back after);\n"
"prints each run's peak skew (the difference of the sides' following\n"
"errors) and how much the coupling cuts it.\n"
"  --gantry             the pair's test\n"
"  --gantry --auto      choose gantry_kp, _ti, _td: ramps of the pair with\n"
"                       candidate gains, each kept when it cuts the peak\n"
"                       skew and holds with gantry_kp raised by the gain\n"
"                       margin (--gain-margin, default 8 dB); prints the\n"
"                       peak skew with the chosen gains, none and the\n"
"                       card's; --apply writes the three (all or none)\n"
"  -h, --help           this help\n"
"  -V, --version        versions\n"
"\n"
"Exit status: 0 done, 1 the card or the library failed (or a bound\n"
"refused the step: nothing moved), 2 usage error, 3 device, 4 fault\n"
"latched, 6 gnuplot missing or failed, 7 stopped by SIGINT or SIGTERM\n"
"(the motion stopped on its way, the card's limits and timing put back),\n"
"8 aborted on the following-error limit (axis back at its start);\n"
"--auto: 1 also when the design is refused (nothing written); --gantry: 1\n"
"(--auto: also when no gains are acceptable, nothing written)\n"
"also when the card has no pair or AXIS is not a side of it (nothing moved),\n"
"4 also when the skew limit latched SKEW.\n");
}

static int number(const char *opt, const char *v, double lo, double *out)
{
	if (sh2000_tool_double(v, out) < 0 || *out <= lo)
		return sh2000_tool_usage(NULL, "%s: '%s' is not a number above %g",
					 opt, v, lo);
	return 0;
}

/* --auto's options together (after the axis and the common ones). */
static int check_auto(struct tune_opts *o, int auto_only, int tests)
{
	if (!o->autotune)
		return sh2000_tool_usage(NULL, "--%s needs --auto",
					 o->apply ? "apply" : o->save ? "save" :
					 o->dry_run ? "dry-run" :
					 auto_only ? "bandwidth, --margin or --gain-margin" : "auto");
	if (tests > 1 || o->test != TUNE_TEST_STEP)
		return sh2000_tool_usage(NULL, "--auto: not with --ramp or --chirp");
	if (o->dry_run && (o->apply || o->save || o->plot || o->csv))
		return sh2000_tool_usage(NULL, "--dry-run writes nothing: not with --%s",
					 o->apply ? "apply" : o->save ? "save" :
					 o->plot ? "plot" : "csv");
	if (o->margin_deg < 20 || o->margin_deg > 89)
		return sh2000_tool_usage(NULL, "--margin: %g is not a phase margin 20..89 degrees",
					 o->margin_deg);
	if (o->gm_db < 3 || o->gm_db > 30)
		return sh2000_tool_usage(NULL, "--gain-margin: %g is not a gain margin 3..30 dB",
					 o->gm_db);
	if (o->hold_s > 10)
		return sh2000_tool_usage(NULL, "--hold: at most 10 s");
	if (!(o->travel_mm > 0))
		o->travel_mm = TUNE_AUTO_TRAVEL_MM;
	return 0;
}

/* --gantry's options together: a ramp, no pictures; with --auto,
 * --apply or --dry-run and --gain-margin (the search measures a gain
 * margin, not a phase margin or a bandwidth). */
static int check_gantry(struct tune_opts *o, int tests, int auto_only)
{
	if (!o->autotune && (o->apply || o->dry_run || auto_only))
		return sh2000_tool_usage(NULL, "--gantry: --%s needs --auto",
					 o->apply ? "apply" : o->dry_run ? "dry-run" : "gain-margin");
	if (o->save)
		return sh2000_tool_usage(NULL, "--gantry: not with --save (sh2000ctl params save keeps the card's gains)");
	if (o->bandwidth_hz || o->margin_deg != TUNE_DEFAULT_MARGIN)
		return sh2000_tool_usage(NULL, "--gantry --auto: not with --bandwidth or --margin (it measures a gain margin: --gain-margin)");
	if (o->apply && o->dry_run)
		return sh2000_tool_usage(NULL, "--dry-run writes nothing: not with --apply");
	if (o->gm_db < 3 || o->gm_db > 30)
		return sh2000_tool_usage(NULL, "--gain-margin: %g is not a gain margin 3..30 dB",
					 o->gm_db);
	if (tests > 1 || (tests && o->test != TUNE_TEST_RAMP))
		return sh2000_tool_usage(NULL, "--gantry ramps the pair (--ramp MM/S): not with --step or --chirp");
	if (o->csv || o->plot)
		return sh2000_tool_usage(NULL, "--gantry: not with --csv or --plot");
	o->test = TUNE_TEST_RAMP;
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
		/* --auto */
		{ "auto", no_argument, NULL, 'U' },
		{ "apply", no_argument, NULL, 'Y' },
		{ "save", required_argument, NULL, 'S' },
		{ "dry-run", no_argument, NULL, 'n' },
		{ "bandwidth", required_argument, NULL, 'B' },
		{ "margin", required_argument, NULL, 'M' },
		{ "gain-margin", required_argument, NULL, 'G' },
		{ "enable", no_argument, NULL, 'e' },
		{ "gantry", no_argument, NULL, 'g' },
		{ "csv", required_argument, NULL, 'c' },
		{ "plot", required_argument, NULL, 'p' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	int c, r = 0, tests = 0, ax, auto_only = 0;
	long l;

	memset(o, 0, sizeof(*o));
	o->ferr_max_mm = 0.1;
	o->hold_s = 0.2;
	o->amplitude_mm = TUNE_CHIRP_AMPLITUDE;
	o->duration_s = TUNE_CHIRP_DURATION;
	o->margin_deg = TUNE_DEFAULT_MARGIN;
	o->gm_db = TUNE_MIN_GM_DB;
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
		/* --auto */
		case 'U': o->autotune = 1; break;
		case 'Y': o->apply = 1; break;
		case 'S': o->save = optarg; break;
		case 'n': o->dry_run = 1; break;
		case 'B': auto_only = 1; r = number("--bandwidth", optarg, 0, &o->bandwidth_hz); break;
		case 'M': auto_only = 1; r = number("--margin", optarg, 0, &o->margin_deg); break;
		case 'G': auto_only = 1; r = number("--gain-margin", optarg, 0, &o->gm_db); break;
		case 'e': o->enable = 1; break;
		case 'g': o->gantry = 1; break;
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
	if (o->gantry)
		return check_gantry(o, tests, auto_only);
	if (o->autotune || o->apply || o->save || o->dry_run || auto_only)
		return check_auto(o, auto_only, tests);
	if (tests != 1)
		return sh2000_tool_usage(NULL, tests ? "one test at a time: --step, --ramp or --chirp" :
					 "which test? --step MM, --ramp MM/S, --chirp F0:F1 or --auto");
	if (o->hold_s > 10)
		return sh2000_tool_usage(NULL, "--hold: at most 10 s");
	return tune_check_options(o);
}

static int outputs_writable(const struct tune_opts *o)
{
	int r = sh2000_tool_writable("--save", o->save);

	if (!r)
		r = sh2000_tool_writable("--csv", o->csv);
	if (!r)
		r = sh2000_tool_writable("--plot", o->plot);
	return r;
}

int main(int argc, char **argv)
{
	struct tune_opts o;
	struct sh2000 *h = NULL;
	int r;

	sh2000_tool_init("sh2000-tune");
	r = parse(argc, argv, &o);
	if (r)
		return r < 0 ? SH2000_EXIT_OK : r;
	if ((r = outputs_writable(&o)))
		return r;
	/* the test moves look at sh2000_tool_stop_asked() between batches
	 * and after each move; a second signal ends the program at once */
	sh2000_tool_catch_stop(SH2000_SECOND_KILLS);
	if ((r = sh2000_tool_open(&h, o.device_arg)))
		return r;
	/* The in-process card is this program's alone and starts with every
	 * axis disabled: no other program can have enabled it, so the test
	 * does (as --enable: disabled again after). */
	if (sh2000_backend(h) == SH2000_BACKEND_SIM)
		o.enable = 1;
	if (o.gantry) {
		r = o.autotune ? tune_run_gantry_auto(h, &o) : tune_run_gantry(h, &o);
		sh2000_close(h);
		return r;
	}
	/* ramp and chirp tests */
	if (o.test != TUNE_TEST_STEP) {
		r = o.test == TUNE_TEST_RAMP ? tune_run_ramp(h, &o) : tune_run_chirp(h, &o, NULL);
		sh2000_close(h);
		return r;
	}
	if (o.autotune)
		r = tune_auto(h, &o);
	else
		r = tune_run_step(h, &o, "");
	sh2000_close(h);
	return r;
}
