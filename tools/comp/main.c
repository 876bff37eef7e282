// SPDX-License-Identifier: MIT
/*
 * sh2000-comp: compensation tables for the card (sh2000-comp(1),
 * docs/compensation.md).
 *
 *   sh2000-comp csv AXIS LASER.csv [--cross AXIS2] [-o TABLE]
 *   sh2000-comp calibrate [-d sim] [--travel LO:HI] [--step MM]
 *               [--grid MM] [--passes N] [-q] [-o TABLE]
 *
 * Its own tool rather than a sh2000ctl sub-command: it links the card
 * model (the simulated interferometer is libsh2000-sim's), which
 * sh2000ctl, a tool for real cards, must not need.
 */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "calib.h"
#include "toolcommon.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000-comp csv AXIS LASER.csv [--cross AXIS2] [-d DEVICE] [-o TABLE]\n"
"       sh2000-comp calibrate [-d sim] [--travel LO:HI] [--step MM] [--grid MM]\n"
"                   [--passes N] [-q] [-o TABLE]\n"
"Write the card's compensation table file (sh2000ctl comp load TABLE).\n"
"  csv        AXIS's pitch from a laser system's export (nominal,measured mm);\n"
"             --cross AXIS2: AXIS2's straightness along AXIS (nominal,deviation);\n"
"             checked as `sh2000ctl comp load` will, with the scales and\n"
"             limits of the card -d names (else $SH2000_DEVICE, else sim),\n"
"             before it is written\n"
"  calibrate  on the simulated machine (-d sim): measure it with its\n"
"             interferometer over lines and an X-Y grid, load the tables\n"
"             and measure again (--passes, 2)\n"
"  -o TABLE   write there (default: standard output)\n"
"  --travel LO:HI  mm around where the machine stands (-250:250)\n"
"  --step MM  spacing of the pitch and straightness points (1)\n"
"  --grid MM  spacing of the flatness grid (25)\n"
"  -q         quiet: no progress on standard error\n");
}

static int out_tables(const struct cal_tables *t, const char *out,
		      const char *comment)
{
	int r = out ? cal_tables_save(t, out, comment) :
		cal_tables_write(t, stdout, comment);

	if (r < 0) {
		sh2000_tool_msg("%s: %s", out ? out : "stdout", strerror(-r));
		return SH2000_EXIT_CARD;
	}
	return SH2000_EXIT_OK;
}

/* A soft limit the table moves the tool beyond, in the library's words. */
static void warn_reach(const char *words)
{
	sh2000_tool_msg("warning: %s", words);
}

/* The CSV read, then checked with the card's scales and limits as
 * `sh2000ctl comp load` will check it; written only when the card would
 * take it. */
static int csv_table(struct cal_tables *t, int a, int cross, const char *csv,
		     const char *dev, const char *out)
{
	struct cal_line *l = cross < 0 ? &t->pitch[a] : cross == 1 ?
			     &t->cross_yx : &t->cross_xy;
	unsigned int *lines = calloc(CAL_MAX_POINTS, sizeof(*lines));
	struct sh2000 *h = NULL;
	char msg[768];
	int r;

	if (!lines)
		return SH2000_EXIT_CARD;
	r = cal_from_csv(l, lines, csv, cross >= 0, msg, sizeof(msg));
	if (r < 0) {
		sh2000_tool_msg("%s", msg);
		free(lines);
		/* errors in the CSV; one that cannot be read is any tool's 1 */
		return r == -1 ? SH2000_EXIT_INPUT : SH2000_EXIT_CARD;
	}
	r = sh2000_tool_open(&h, dev);
	if (r == SH2000_EXIT_OK) {
		r = cal_csv_check(t, lines, l->n - 2, csv, h, warn_reach, msg,
				  sizeof(msg));
		if (r < 0)
			sh2000_tool_msg("%s", msg);
		r = r == -SH2000_EPARAM ? SH2000_EXIT_INPUT :
		    r < 0 ? sh2000_tool_exit_code(r) : out_tables(t, out, csv);
		sh2000_close(h);
	}
	free(lines);
	return r;
}

static int cmd_csv(int argc, char **argv, const char *dev, const char *out,
		   int cross)
{
	struct cal_tables *t;
	int a, r;

	if (argc != 2)
		return sh2000_tool_usage("csv", "want: csv AXIS LASER.csv");
	a = sh2000_tool_axis(argv[0]);
	if (a < 0)
		return sh2000_tool_usage("csv", "'%s' is not an axis (x y z a)", argv[0]);
	if (cross == a || (cross >= 0 && !((a == 0 && cross == 1) ||
					   (a == 1 && cross == 0))))
		return sh2000_tool_usage("csv", "--cross: Y along X or X along Y");
	t = calloc(1, sizeof(*t));
	if (!t)
		return SH2000_EXIT_CARD;
	r = csv_table(t, a, cross, argv[1], dev, out);
	free(t);
	return r;
}

static int parse_travel(const char *s, struct cal_config *c)
{
	double lo, hi;
	char tail;
	unsigned int a;

	if (sscanf(s, "%lf:%lf%c", &lo, &hi, &tail) != 2 || !(lo < hi))
		return -1;
	for (a = 0; a < SH2000_AXES; a++) {
		c->lo[a] = lo;
		c->hi[a] = hi;
	}
	return 0;
}

static int cmd_calibrate(const char *dev, const struct cal_config *c,
			 const char *out)
{
	char tmp[] = "/tmp/sh2000-comp-XXXXXX", msg[512];
	struct cal_tables *t = calloc(1, sizeof(*t));
	struct cal_sim s;
	int fd, r;

	if (!t)
		return SH2000_EXIT_CARD;
	if (strcmp(dev, "sim")) {
		free(t);
		sh2000_tool_msg("calibrate: %s: only the in-process simulated machine (-d sim) has an interferometer this tool reads; on a real machine export the laser's CSV and use `sh2000-comp csv`", dev);
		return SH2000_EXIT_USAGE;
	}
	fd = mkstemp(tmp);
	if (fd < 0) {
		free(t);
		return SH2000_EXIT_CARD;
	}
	close(fd);
	r = cal_sim_open(&s, NULL, NULL, tmp, msg, sizeof(msg));
	if (r < 0) {
		sh2000_tool_msg("%s", msg);
		r = sh2000_tool_exit_code(r);
	} else {
		r = cal_run(&s, c, t);
		if (r < 0)
			r = sh2000_tool_fail(s.h, r, "calibrate");
		else
			r = out_tables(t, out, "calibrated on the simulated machine");
		cal_sim_close(&s);
	}
	unlink(tmp);
	free(t);
	return r;
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "output", required_argument, NULL, 'o' },
		{ "device", required_argument, NULL, 'd' },
		{ "cross", required_argument, NULL, 'c' },
		{ "travel", required_argument, NULL, 't' },
		{ "step", required_argument, NULL, 's' },
		{ "grid", required_argument, NULL, 'g' },
		{ "passes", required_argument, NULL, 'p' },
		{ "quiet", no_argument, NULL, 'q' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	struct cal_config c;
	const char *out = NULL, *dev = NULL, *env;
	int o, cross = -1;
	long n;

	sh2000_tool_init("sh2000-comp");
	cal_config_default(&c);
	c.verbose = 1;
	while ((o = getopt_long(argc, argv, "o:d:qhV", opts, NULL)) != -1) {
		switch (o) {
		case 'o': out = optarg; break;
		case 'd': dev = optarg; break;
		case 'q': c.verbose = 0; break;
		case 'c':
			if ((cross = sh2000_tool_axis(optarg)) < 0)
				return sh2000_tool_usage(NULL, "--cross: '%s' is not an axis", optarg);
			break;
		case 't':
			if (parse_travel(optarg, &c) < 0)
				return sh2000_tool_usage(NULL, "--travel: want LO:HI in mm, LO < HI");
			break;
		case 's':
		case 'g':
			if (sh2000_tool_double(optarg, o == 's' ? &c.step_mm : &c.grid_mm) < 0 ||
			    (o == 's' ? c.step_mm : c.grid_mm) <= 0)
				return sh2000_tool_usage(NULL, "--%s: a positive spacing in mm",
							 o == 's' ? "step" : "grid");
			break;
		case 'p':
			if (sh2000_tool_long(optarg, 1, 10, &n) < 0)
				return sh2000_tool_usage(NULL, "--passes: 1..10");
			c.passes = (unsigned int)n;
			break;
		case 'h': usage(stdout); return SH2000_EXIT_OK;
		case 'V': sh2000_tool_print_version(SH2000_TOOLS_VERSION); return SH2000_EXIT_OK;
		default: usage(stderr); return SH2000_EXIT_USAGE;
		}
	}
	if (optind >= argc) {
		usage(stderr);
		return SH2000_EXIT_USAGE;
	}
	/* csv checks against the card the table is for: -d, else the one
	 * $SH2000_DEVICE names for every tool, else the simulated card's
	 * defaults (a conversion must work where no card is present);
	 * calibrate has only the in-process card's interferometer */
	env = getenv("SH2000_DEVICE");
	if (!strcmp(argv[optind], "csv"))
		return cmd_csv(argc - optind - 1, argv + optind + 1,
			       dev ? dev : env && *env ? env : "sim", out, cross);
	if (!strcmp(argv[optind], "calibrate") && optind + 1 == argc)
		return cmd_calibrate(dev ? dev : "sim", &c, out);
	return sh2000_tool_usage(NULL, "unknown command '%s' (csv, calibrate)", argv[optind]);
}
