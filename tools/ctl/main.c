/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl: operate and commission an SH-2000TH card (status, parameters,
 * enable, jog, move, home, stop, estop, reset, data gathering, RAM dump). sh2000ctl(1) is
 * the manual; this file holds the command table, the global options and
 * the "+" that chains subcommands on one handle.
 */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif


static const struct ctl_cmd cmds[] = {
	{ "info", ctl_info, "",
	  "Show the device, the card's protocol version, its timing, each axis'\n"
	  "scale, the port cycles of this handle and the versions involved.\n" },
	{ "status", ctl_status, "[--json] [--watch [SECONDS]] [--count N]",
	  "Show the card state, latched faults, queue and each axis' position,\n"
	  "set-point, following error, DAC code, state bits and faults.\n"
	  "  --json            one JSON object (with --watch: one per line)\n"
	  "  --watch [SECONDS] repeat every SECONDS (default 1) until SIGINT\n"
	  "  --count N         with --watch: stop after N reports\n"
	  "Exit status 4 when a fault or an emergency stop is latched.\n" },
	{ "params", ctl_params,
	  "[AXIS|global [NAME[=VALUE]]...] | load FILE | save FILE",
	  "Get and set parameters in user units (mm, mm/s, mm/s^2, s, card\n"
	  "units). AXIS is x, y, z, a (or 0..3); 'global' the card-wide ones.\n"
	  "  params                   every parameter of every axis, and globals\n"
	  "  params x                 every parameter of axis x\n"
	  "  params x kp vmax         those values, one per line\n"
	  "  params x kp=0.5 vmax=300 set them: all are checked first, nothing\n"
	  "                           is sent if any is bad\n"
	  "  params global host_timeout_ms=200\n"
	  "  params save FILE         write every parameter to FILE ('-': stdout)\n"
	  "  params load FILE         check the whole FILE, then set it; an error\n"
	  "                           names FILE:LINE and nothing is set\n"
	  "FILE format: lines 'name = value', sections [x] [y] [z] [a] [global],\n"
	  "'#' or ';' comments (see sh2000ctl(1)).\n" },
	{ "enable", ctl_enable, "AXES...",
	  "Close the servo loop of AXES: x y z a, lists like x,y or xyz, or all.\n" },
	{ "disable", ctl_disable, "AXES...",
	  "Open the servo loop of AXES (DAC 0): x y z a, x,y, xyz or all.\n" },
	{ "jog", ctl_jog,
	  "AXIS DISTANCE [--speed MM/S] | AXIS --velocity MM/S --time SECONDS",
	  "Move one enabled axis relative to where it is: DISTANCE mm (signed)\n"
	  "at --speed (default: as fast as vmax and amax allow), or at a signed\n"
	  "--velocity for --time seconds. The motion is planned within the\n"
	  "axis' vmax, amax and soft limits and ends at rest.\n" },
	{ "move", ctl_move, "AXIS=POS... [--feed MM/S]",
	  "Move the named enabled axes to the absolute positions POS (mm) on one\n"
	  "straight line, starting and ending at rest, at --feed mm/s along the\n"
	  "path (default: as fast as the axes allow). Targets outside the soft\n"
	  "limits are refused before anything moves.\n" },
	{ "home", ctl_home, "AXIS [--index] [--timeout SECONDS]",
	  "Home one enabled axis on its home switch (--index: finish on the\n"
	  "encoder index) and wait until it is done, up to --timeout seconds\n"
	  "(default 120). The card needs a polling host while it homes, so the\n"
	  "command always waits. SIGINT, SIGTERM (exit 7) or the timeout (exit 1)\n"
	  "stop the card and wait for rest: nothing is latched.\n" },
	{ "index", ctl_index,
	  "AXIS [--mask | --mask-invert] [--invert] [--within MM] [--wait]\n"
	  "       [--timeout SECONDS] | AXIS --wait [--timeout SECONDS]",
	  "Arm the index latch of one enabled axis (protocol 1.6), whether the\n"
	  "card runs a motion or idles: the next index mark is latched (as\n"
	  "LinuxCNC's index-enable through hal_sh2000). Returns at once unless\n"
	  "--wait; '--wait' alone waits for the arm made before, e.g.\n"
	  "'index x --mask + jog x --velocity -1 --time 2 + index x --wait'.\n"
	  "  --mask          only a mark seen while the home switch is active\n"
	  "  --mask-invert   only one seen while it is inactive\n"
	  "  --invert        the mark's rising edge (entering it), not its\n"
	  "                  falling edge (hostmot2's index-invert)\n"
	  "  --within MM     no mark within MM of travel ends the arm (missed)\n"
	  "  --wait          wait until a mark is latched (up to --timeout,\n"
	  "                  default 120 s) and print 'x index at MM mm (cycle N)'\n" },
	{ "stop", ctl_stop, "[--no-wait]",
	  "Controlled stop: the card decelerates within amax and discards its\n"
	  "queue; waits until it is at rest unless --no-wait.\n" },
	{ "estop", ctl_estop, "",
	  "Emergency stop: latched at once (set-points frozen) until 'reset'.\n" },
	{ "reset", ctl_reset, "",
	  "Clear latched faults and a latched emergency stop; the card goes idle.\n"
	  "Enabled axes stay enabled; axes a fault disabled stay disabled.\n" },
	{ "gather", ctl_gather,
	  "[--axis AXES] [--signals LIST] [--period CYCLES] [--samples N]\n"
	  "       [--trigger now|motion|fault] [--pretrigger N] [--timeout SECONDS]\n"
	  "       [-o FILE] | --no-wait [...] | --read [-o FILE] [--timeout SECONDS]",
	  "Record signals on the card every PERIOD servo cycles and write them as\n"
	  "CSV: a header row 'time[s],x.setpoint[counts],...', then one row per\n"
	  "sample, time measured from the trigger (pre-trigger rows negative).\n"
	  "  -a, --axis AXES     x, x,y, xyz or all (default x)\n"
	  "  -s, --signals LIST  comma-separated: setpoint encoder ferr dac pid_p\n"
	  "                      pid_i pid_d ff velocity setpoint_vel, or all\n"
	  "                      (default setpoint,encoder,ferr,dac)\n"
	  "  --period CYCLES     servo cycles per sample, 1..65535 (default 1)\n"
	  "  --samples N         samples in the record (default 1000; the card\n"
	  "                      holds 32768 values in all)\n"
	  "  --trigger WHEN      now (default), motion (the next motion's start)\n"
	  "                      or fault (the next fault or emergency stop)\n"
	  "  --pretrigger N      samples kept from before the trigger (not with now)\n"
	  "  --timeout SECONDS   wait at most this long for the record (default 60)\n"
	  "  -o, --output FILE   the CSV file (default '-': stdout); written only\n"
	  "                      when the whole record was read\n"
	  "  --no-wait           only arm the record (then e.g. '+ move ...')\n"
	  "  --read              only wait for the card's record and write it\n"
	  "Units are the card's: counts, DAC codes, counts/s.\n" },
	{ "comp", ctl_comp, "load FILE | show [FILE] | clear",
	  "The card's compensation tables (protocol 1.5, docs/compensation.md):\n"
	  "  comp load FILE   read the table file, check it against the card's\n"
	  "                   vmax and amax, send it and switch to it at rest;\n"
	  "                   an error names FILE:LINE and nothing changes\n"
	  "  comp show [FILE] the active tables' identity and sum (and whether\n"
	  "                   FILE is them)\n"
	  "  comp clear       no tables (switched at rest)\n"
	  "Exit status 5 when the file is refused.\n" },
	{ "dump", ctl_dump, "[RANGE...]",
	  "Print dual-port RAM words as hex, 8 per line after the word offset\n"
	  "(hex). RANGE: N, N-M (inclusive), N+COUNT or all; numbers decimal\n"
	  "or 0x hex, words 0..1023. Default: all.\n" },
};

#define NCMDS (sizeof(cmds) / sizeof(cmds[0]))

static const struct ctl_cmd *find_cmd(const char *name)
{
	for (size_t i = 0; i < NCMDS; i++)
		if (!strcmp(cmds[i].name, name))
			return &cmds[i];
	return NULL;
}

void ctl_print_help(const char *name, FILE *f)
{
	const struct ctl_cmd *c = find_cmd(name);

	if (!c)
		return;
	fprintf(f, "Usage: sh2000ctl [-d DEVICE] %s%s%s\n%s", c->name,
		c->synopsis[0] ? " " : "", c->synopsis, c->help);
}

int ctl_want_help(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--"))
			break;
		if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
			ctl_print_help(argv[0], stdout);
			return 1;
		}
	}
	return 0;
}

int ctl_is_option(const char *a)
{
	return a[0] == '-' && (isalpha((unsigned char)a[1]) ||
			       (a[1] == '-' && a[2]));
}

int ctl_opt_value(int argc, char **argv, int *i, const char *lng, char shrt,
		  const char **val)
{
	const char *a = argv[*i];
	size_t n = strlen(lng);

	if (!strncmp(a, lng, n) && a[n] == '=') {
		*val = a + n + 1;
		return 1;
	}
	if (strcmp(a, lng) && !(shrt && a[0] == '-' && a[1] == shrt && !a[2]))
		return 0;
	if (*i + 1 >= argc) {
		sh2000_tool_usage(argv[0], "%s: option %s needs a value", argv[0],
				  a);
		return -1;
	}
	*val = argv[++*i];
	return 1;
}

int ctl_open(struct ctl *c)
{
	if (c->h)
		return 0;
	return sh2000_tool_open(&c->h, c->device_arg);
}

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000ctl [-d DEVICE] COMMAND [ARGS...] [+ COMMAND [ARGS...]]...\n"
"Operate an SH-2000TH motion card.\n"
"\n"
"  -d, --device DEVICE  /dev/sh2000-N, io:0xNNN, sim or sim:NAME\n"
"                       (default $SH2000_DEVICE, else /dev/sh2000-0)\n"
"  -h, --help           this help ('sh2000ctl COMMAND --help' for one)\n"
"  -V, --version        tool, library, protocol and driver ABI versions\n"
"\n"
"Commands:\n");
	for (size_t i = 0; i < NCMDS; i++)
		fprintf(f, "  %-8s %s\n", cmds[i].name, cmds[i].synopsis);
	fprintf(f,
"\n"
"A '+' chains commands on one open card, e.g. for the in-process 'sim'\n"
"card, which is new at every invocation:\n"
"  sh2000ctl -d sim enable x + move x=310 + status\n"
"\n"
"Exit status: 0 ok, 1 the card or a command failed, 2 usage error,\n"
"3 the device cannot be opened, 4 a fault or emergency stop is latched,\n"
"7 jog, move or home stopped by a signal or by another program's STOP.\n");
}

static void version(void)
{
	sh2000_tool_print_version(SH2000_TOOLS_VERSION);
}

int main(int argc, char **argv)
{
	struct ctl c = { 0 };
	int i = 1, rc = SH2000_EXIT_OK;

	sh2000_tool_init("sh2000ctl");
	/* global options, up to the first command */
	while (i < argc && argv[i][0] == '-') {
		const char *a = argv[i], *v;
		int k;

		if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
			usage(stdout);
			return SH2000_EXIT_OK;
		}
		if (!strcmp(a, "-V") || !strcmp(a, "--version")) {
			version();
			return SH2000_EXIT_OK;
		}
		if (!strcmp(a, "--")) {
			i++;
			break;
		}
		if ((!strcmp(a, "-d") || !strcmp(a, "--device")) && i + 1 >= argc)
			return sh2000_tool_usage(NULL, "option %s needs a DEVICE", a);
		k = ctl_opt_value(argc, argv, &i, "--device", 'd', &v);
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (k == 0)
			return sh2000_tool_usage(NULL, "unknown option '%s'", a);
		/* an empty one is the library's: $SH2000_DEVICE, as in every tool */
		c.device_arg = v;
		i++;
	}
	if (i >= argc)
		return sh2000_tool_usage(NULL, "missing COMMAND");
	if (!strcmp(argv[i], "help")) {
		if (i + 1 < argc && find_cmd(argv[i + 1]))
			ctl_print_help(argv[i + 1], stdout);
		else if (i + 1 < argc)
			return sh2000_tool_usage(NULL, "unknown command '%s'",
						 argv[i + 1]);
		else
			usage(stdout);
		return SH2000_EXIT_OK;
	}
	/* check every command name of a chain before running any */
	for (int j = i, first = 1; j < argc; j++) {
		if (first && !find_cmd(argv[j]))
			return sh2000_tool_usage(NULL, "unknown command '%s'",
						 argv[j]);
		first = !strcmp(argv[j], "+");
		if (first && j + 1 == argc)
			return sh2000_tool_usage(NULL, "'+' at the end: a command must follow");
	}
	while (i < argc && rc == SH2000_EXIT_OK) {
		int end = i;
		const struct ctl_cmd *cmd = find_cmd(argv[i]);

		while (end < argc && strcmp(argv[end], "+"))
			end++;
		argv[end < argc ? end : argc] = NULL;
		rc = cmd->fn(&c, end - i, argv + i);
		fflush(stdout);
		i = end + 1;
	}
	if (c.h)
		sh2000_close(c.h);
	return rc;
}
