/* SPDX-License-Identifier: MIT */
/* sh2000ctl's internal interface: one file per group of subcommands. */
#ifndef SH2000CTL_H
#define SH2000CTL_H

#include <stdio.h>

#include <sh2000/sh2000.h>

#include "toolcommon.h"

struct ctl {
	const char *device_arg;	/* -d/--device, NULL: $SH2000_DEVICE/default */
	struct sh2000 *h;	/* opened on the first subcommand needing it */
};

/* Open the card unless already open: 0 or SH2000_EXIT_DEVICE. */
int ctl_open(struct ctl *c);

/* A subcommand: argv[0] is its name; returns an exit code. */
typedef int (*ctl_cmd_fn)(struct ctl *c, int argc, char **argv);

struct ctl_cmd {
	const char *name;
	ctl_cmd_fn fn;
	const char *synopsis;	/* after "sh2000ctl [-d DEVICE] NAME " */
	const char *help;	/* the rest of its --help */
};

/* The subcommands (tables in each file). */
int ctl_info(struct ctl *c, int argc, char **argv);
int ctl_status(struct ctl *c, int argc, char **argv);
int ctl_params(struct ctl *c, int argc, char **argv);
int ctl_enable(struct ctl *c, int argc, char **argv);
int ctl_disable(struct ctl *c, int argc, char **argv);
int ctl_jog(struct ctl *c, int argc, char **argv);
int ctl_move(struct ctl *c, int argc, char **argv);
int ctl_home(struct ctl *c, int argc, char **argv);
int ctl_index(struct ctl *c, int argc, char **argv);
int ctl_stop(struct ctl *c, int argc, char **argv);
int ctl_estop(struct ctl *c, int argc, char **argv);
int ctl_reset(struct ctl *c, int argc, char **argv);
int ctl_dump(struct ctl *c, int argc, char **argv);
int ctl_gather(struct ctl *c, int argc, char **argv);
int ctl_comp(struct ctl *c, int argc, char **argv);
/* After comp load: each corrected axis' correction inside its soft limits,
 * a warning where it carries the tool beyond one (compreach.c). */
int ctl_comp_reach(struct ctl *c, const char *file);

/* --help of a subcommand on stdout; 1 if argv holds -h/--help (then the
 * subcommand returns 0 at once). */
int ctl_want_help(int argc, char **argv);
void ctl_print_help(const char *name, FILE *f);

/* Option parsing without getopt, so that "-5" is a number, not an option:
 * an option is "-" followed by a letter, or "--" followed by text. */
int ctl_is_option(const char *arg);
/* If argv[*i] is --long/-s with a value ("--long V", "--long=V", "-s V"):
 * sets *val, advances *i past the value, returns 1; 0 if not this option;
 * -1 (message printed) when the value is missing. */
int ctl_opt_value(int argc, char **argv, int *i, const char *lng, char shrt,
		  const char **val);

/* pair.c: 1 when the card's protocol has parameter id. */
int ctl_card_has(struct ctl *c, unsigned int id);

/* The card's gantry pair (protocol 1.7) as status shows it. */
struct ctl_pair {
	int on;			/* a pair is configured */
	unsigned int axis[2];	/* side a, side b */
	double kp, ti, td;	/* the coupling loop */
	long long limit_counts, square_counts;
	long long skew_counts;	/* e_a - e_b from this status */
	double skew_mm;
	int fault;		/* SKEW latched on a side */
};

struct json_object;
/* p->on = 0 on a card without a pair or before 1.7; an exit code when a
 * parameter cannot be read. */
int ctl_pair_get(struct ctl *c, const struct sh2000_status *st,
		 struct ctl_pair *p);
void ctl_pair_print(const struct ctl_pair *p);
/* NULL (JSON null) without a pair. */
struct json_object *ctl_pair_json(const struct ctl_pair *p);

/* Axis parameters in user units that are lengths (mm, mm/s, mm/s^2). */
int ctl_param_is_mm(unsigned int id);

#endif /* SH2000CTL_H */
