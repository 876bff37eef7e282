/* SPDX-License-Identifier: MIT */
/*
 * A bounded test move of one axis (step.c), shared by the step test and
 * the identification's excitation (ident.c): the card idle, the axis
 * enabled, the user's following-error and DAC bounds on the card during
 * the move and put back after; beyond the following-error bound the card
 * is reset and the axis goes back to its start.
 */
#ifndef SH2000_TUNE_TESTMOVE_H
#define SH2000_TUNE_TESTMOVE_H

#include <stddef.h>
#include <stdint.h>

#include <sh2000/path.h>

#include "tune.h"

struct tune_move {
	struct sh2000 *h;
	const struct tune_opts *o;
	unsigned int a;
	struct sh2000_path_config pc;
	int32_t p[SH2000_AXES];	/* every axis' set-point, counts */
	int32_t start, d;	/* counts (d: the step test's step) */
	double ferr0, dac0;	/* the card's limits before the test */
	int enabled_by_us;
};

/* The message of a library error, as the tools print it: an exit code. */
int tune_move_fail(struct tune_move *s, int r, const char *what);
/* Card idle, axis enabled, planner configuration and start taken: an
 * exit code (nothing moved when not 0). */
int tune_move_begin(struct tune_move *s);
/* Disable the axis if tune_move_begin() enabled it. */
void tune_move_end(struct tune_move *s);
/* The velocity bound: --vmax or the axis' vmax, the lower, mm/s. */
double tune_move_vmax(const struct tune_move *s);
/* The user's following-error and DAC bounds on the card (all or none),
 * and back: exit codes. */
int tune_move_limits(struct tune_move *s);
int tune_move_restore(struct tune_move *s);
/* After a following-error fault (fault) of `test`: reset, limits back,
 * axis enabled and moved back to its start. TUNE_EXIT_ABORTED or an exit
 * code. */
int tune_move_recover(struct tune_move *s, int fault, const char *test);
/* n coarse points with the axis at v counts (flags on the last). */
int tune_move_hold(struct tune_move *s, int32_t v, unsigned int n,
		   unsigned int flags);
/* n coarse points, the axis at v[0..n) counts (flags on the last). */
int tune_move_points(struct tune_move *s, const int32_t *v, size_t n,
		     unsigned int flags);

#endif /* SH2000_TUNE_TESTMOVE_H */
