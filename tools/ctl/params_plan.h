/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl params: the plan of values to set, from the command line or a
 * parameter file, before anything is checked against a card or sent.
 *
 * File format (also what `params save` writes):
 *     # comment            ; comment too
 *     [global]
 *     host_timeout_ms = 100
 *     [x]                  (x y z a, or 0..3)
 *     kp = 0.5
 *     vmax = 400           (mm/s; units as `sh2000ctl params` shows them)
 */
#ifndef SH2000CTL_PARAMS_PLAN_H
#define SH2000CTL_PARAMS_PLAN_H

#include <stdio.h>

#include <sh2000/sh2000.h>

#include "toolcommon.h"

#define CTL_SECT_GLOBAL SH2000_AXES	/* index of the global section */

struct ctl_plan {
	const char *file;	/* NULL: command line */
	const char *dev;	/* device, once open (command-line messages) */
	int set[SH2000_AXES + 1][SH2000_GP_END];
	double v[SH2000_AXES + 1][SH2000_GP_END];
	int line[SH2000_AXES + 1][SH2000_GP_END];
	int errors;
};

/* "x" .. "a", "global" for section s. */
const char *ctl_plan_section(unsigned int s);

/* A message naming the file and line (or the device, on the command
 * line); counts an error. */
void ctl_plan_error(struct ctl_plan *p, int line, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/* One "name=value" into the plan for section s (an error if the name is
 * unknown, of the other section, not a number, or given twice). */
void ctl_plan_add(struct ctl_plan *p, unsigned int s, const char *name,
		  const char *value, int line);

/* Every line of f into p (p->file names it in messages; path in a read
 * error). 0, or -1 when p holds errors. */
int ctl_plan_read(struct ctl_plan *p, FILE *f, const char *path);

#endif /* SH2000CTL_PARAMS_PLAN_H */
