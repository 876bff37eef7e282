/* SPDX-License-Identifier: MIT */
/* The identification's test move on the card (ident.c). */
#ifndef SH2000_TUNE_IDENT_H
#define SH2000_TUNE_IDENT_H

#include "autotune.h"
#include "tune.h"

struct tune_ident_result {
	struct tune_plant plant;
	double start;		/* the axis' set-point before and after, counts */
	double amplitude_mm;	/* the excitation's largest excursion */
	double seconds;		/* its length */
};

/*
 * Move axis o->axis with the excitation within o's bounds (travel_mm,
 * vmax, dac_max, ferr_max_mm; o->enable) and fit its plant into res. An
 * exit code: 0, SH2000_EXIT_ABORTED (following-error bound: the axis is back
 * at its start, the card's limits as they were) or another with the
 * message printed.
 */
int tune_ident(struct sh2000 *h, const struct tune_opts *o,
	       struct tune_ident_result *res);

#endif /* SH2000_TUNE_IDENT_H */
