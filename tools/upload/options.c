// SPDX-License-Identifier: MIT
/* sh2000-upload's command line (sh2000-upload(1) is the manual). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "upload.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static void usage(FILE *f)
{
	fprintf(f,
		"Usage: sh2000-upload [-d DEV] [options] FILE\n"
		"Run an NC program (G-code, rs274 canonical output, CSV, JSON NURBS) on an\n"
		"SH-2000TH card. The whole program is read, checked and planned before\n"
		"anything moves.\n"
		"\n"
		"  -d, --device DEV        card: /dev/sh2000-N, io:0xNNN, sim, sim:NAME\n"
		"                          (default $SH2000_DEVICE, else /dev/sh2000-0)\n"
		"  -f, --format FMT        gcode, canon, csv or json (default: from the\n"
		"                          file name: .ngc .nc .gcode .g .tap .cnc .canon\n"
		"                          .csv .json)\n"
		"      --rs274             read G-code through LinuxCNC's rs274 interpreter\n"
		"                          (full RS274NGC; Debian package linuxcnc-uspace)\n"
		"      --tool-table FILE   LinuxCNC tool table (T1 P1 Z+10 D6 ;text, lengths\n"
		"                          in mm) for T words and G43 offsets, in both readers\n"
		"      --parameter-file FILE\n"
		"                          rs274's parameter (.var) file for --rs274 (read,\n"
		"                          not changed; default: an empty one)\n"
		"      --pause-on-tool-change\n"
		"                          wait for the operator at each tool change (M6):\n"
		"                          Enter on the terminal (standard input must be one)\n"
		"  -F, --feed MM_PER_MIN   feed for CSV and JSON files that carry none\n"
		"  -o, --feed-override PCT feed override, 1..200 %% (default 100)\n"
		"      --tolerance MM      path tolerance until the program sets one with\n"
		"                          G61/G64: corners rounded and chords of arcs and\n"
		"                          curves within MM (default 0.01)\n"
		"      --raw               no B-spline compensation (the card's spline\n"
		"                          cuts curves; for comparison)\n"
		"      --trapezoid         acceleration-limited profile instead of S-curves\n"
		"  -n, --dry-run           read, check and plan only; nothing moves\n"
		"  -t, --trace FILE.csv    write t,cmd_x,act_x,...,cmd_a,act_a (s, mm): every\n"
		"                          servo cycle on `sim`, every status poll otherwise\n"
		"      --trace-every N     keep every N-th sample in the trace\n"
		"  -p, --plot FILE.png|svg draw the path, feed and following error (gnuplot)\n"
		"      --optional-stop     M1 pauses like M0 (default: M1 is skipped)\n"
		"      --no-enable         do not enable axes; fail if one is disabled\n"
		"  -q, --quiet             no progress output\n"
		"  -h, --help              this text\n"
		"  -V, --version           version\n"
		"\n"
		"M0 (and M1 with --optional-stop) pauses at rest: press Enter on a terminal;\n"
		"otherwise send a line on standard input or SIGUSR1. SIGUSR2 holds the feed\n"
		"at once (on the card's time base), SIGUSR1 resumes. SIGINT/SIGTERM stop the\n"
		"run on the path (controlled).\n"
		"\n"
		"Exit codes: 0 done, 1 card or I/O error, 2 usage, 3 device cannot be opened,\n"
		"4 card fault or emergency stop, 5 program errors (nothing moved),\n"
		"6 rs274 or gnuplot missing or failed, 7 stopped by the operator.\n");
}

static int parse_format(const char *s, struct upl_opts *o)
{
	static const struct {
		const char *name;
		enum sh2000_prog_format f;
	} names[] = {
		{ "gcode", SH2000_PROG_GCODE }, { "ngc", SH2000_PROG_GCODE },
		{ "canon", SH2000_PROG_CANON }, { "csv", SH2000_PROG_CSV },
		{ "json", SH2000_PROG_NURBS_JSON },
		{ "nurbs", SH2000_PROG_NURBS_JSON },
	};

	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (!strcasecmp(s, names[i].name)) {
			o->format = names[i].f;
			return 0;
		}
	return sh2000_tool_usage(NULL,
				 "--format %s: expected gcode, canon, csv or json",
				 s);
}

/* An option with a number. */
static int parse_value(int c, const char *arg, struct upl_opts *o)
{
	double v;
	long l;

	switch (c) {
	case 'F':
		if (sh2000_tool_double(arg, &v) || !(v > 0.0))
			return sh2000_tool_usage(NULL,
				"--feed %s: expected a feed > 0 in mm/min", arg);
		o->feed_mm_min = v;
		return 0;
	case 'o':
		if (sh2000_tool_double(arg, &v) || !(v >= 1.0) || v > 200.0)
			return sh2000_tool_usage(NULL,
				"--feed-override %s: expected a percentage 1..200",
				arg);
		o->override = v / 100.0;
		return 0;
	case 'L':
		if (sh2000_tool_double(arg, &v) || !(v >= 0.0001) || v > 10.0)
			return sh2000_tool_usage(NULL,
				"--tolerance %s: expected mm from 0.0001 to 10", arg);
		o->tolerance = v;
		return 0;
	default:	/* 'e' */
		if (sh2000_tool_long(arg, 1, 1000000, &l))
			return sh2000_tool_usage(NULL,
				"--trace-every %s: expected an integer 1..1000000",
				arg);
		o->trace_every = (unsigned int)l;
		return 0;
	}
}

static int parse_one(int c, const char *arg, struct upl_opts *o)
{
	switch (c) {
	case 'd': o->device = arg; return 0;
	case 'f': return parse_format(arg, o);
	case 'R': o->rs274 = 1; return 0;
	case 'K': o->tool_table = arg; return 0;
	case 'P': o->parameter_file = arg; return 0;
	case 'C': o->pause_tool_change = 1; return 0;
	case 'F': case 'o': case 'L': case 'e': return parse_value(c, arg, o);
	case 'r': o->raw = 1; return 0;
	case 'T': o->trapezoid = 1; return 0;
	case 'n': o->dry_run = 1; return 0;
	case 't': o->trace = arg; return 0;
	case 'p': o->plot = arg; return 0;
	case 'O': o->optional_stop = 1; return 0;
	case 'E': o->no_enable = 1; return 0;
	case 'q': o->quiet = 1; return 0;
	case 'h':
		usage(stdout);
		exit(SH2000_EXIT_OK);
	case 'V':
		sh2000_tool_print_version(SH2000_TOOLS_VERSION);
		exit(SH2000_EXIT_OK);
	}
	return -1;
}

/* What the options say together. */
static int parse_check(int argc, char **argv, struct upl_opts *o)
{
	if (optind >= argc)
		return sh2000_tool_usage(NULL, "no program file");
	if (optind + 1 < argc)
		return sh2000_tool_usage(NULL, "one program file at a time (got '%s' too)",
					 argv[optind + 1]);
	o->file = argv[optind];
	if (o->plot) {
		size_t n = strlen(o->plot);

		if (n < 5 || (strcasecmp(o->plot + n - 4, ".png") &&
			      strcasecmp(o->plot + n - 4, ".svg")))
			return sh2000_tool_usage(NULL,
				"--plot %s: the name must end in .png or .svg",
				o->plot);
	}
	if (o->rs274 && o->format && o->format != SH2000_PROG_GCODE)
		return sh2000_tool_usage(NULL, "--rs274 reads G-code only");
	if (o->parameter_file && !o->rs274)
		return sh2000_tool_usage(NULL,
			"--parameter-file %s is rs274's: it needs --rs274 (the built-in parser has no parameters)",
			o->parameter_file);
	/* a tool change needs a person who says the tool is in */
	if (o->pause_tool_change && !o->dry_run && !isatty(STDIN_FILENO))
		return sh2000_tool_usage(NULL,
			"--pause-on-tool-change: standard input is not a terminal, so no one could confirm a tool change; run from a terminal (or without the option: tool changes are then reported once)");
	return SH2000_EXIT_OK;
}

int upl_parse(int argc, char **argv, struct upl_opts *o)
{
	static const struct option lo[] = {
		{ "device", required_argument, NULL, 'd' },
		{ "format", required_argument, NULL, 'f' },
		{ "rs274", no_argument, NULL, 'R' },
		{ "tool-table", required_argument, NULL, 'K' },
		{ "parameter-file", required_argument, NULL, 'P' },
		{ "pause-on-tool-change", no_argument, NULL, 'C' },
		{ "feed", required_argument, NULL, 'F' },
		{ "feed-override", required_argument, NULL, 'o' },
		{ "tolerance", required_argument, NULL, 'L' },
		{ "raw", no_argument, NULL, 'r' },
		{ "trapezoid", no_argument, NULL, 'T' },
		{ "dry-run", no_argument, NULL, 'n' },
		{ "trace", required_argument, NULL, 't' },
		{ "trace-every", required_argument, NULL, 'e' },
		{ "plot", required_argument, NULL, 'p' },
		{ "optional-stop", no_argument, NULL, 'O' },
		{ "no-enable", no_argument, NULL, 'E' },
		{ "quiet", no_argument, NULL, 'q' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	int c, r;

	memset(o, 0, sizeof(*o));
	o->override = 1.0;
	o->trace_every = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+d:f:F:o:nt:p:qhV", lo,
				NULL)) != -1) {
		r = c == '?' ? -1 : parse_one(c, optarg, o);
		if (r > 0)
			return r;
		if (r == 0)
			continue;
		if (optopt && strchr("dfFotpeLKP", optopt))
			return sh2000_tool_usage(NULL, "option -%c needs a value",
						 optopt);
		return sh2000_tool_usage(NULL, "unknown option '%s'",
					 argv[optind - 1]);
	}
	return parse_check(argc, argv, o);
}
