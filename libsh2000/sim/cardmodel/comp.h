/* SPDX-License-Identifier: MIT */
/*
 * The firmware's compensation tables (protocol 1.5): the staging memory a
 * load pages into, two table sets (the active one and the one it blends
 * from after a switch) and each cycle's correction of the set-points.
 * Included by cardmodel.h; the code is comp.c.
 */
#ifndef SH2000_CARDMODEL_COMP_H
#define SH2000_CARDMODEL_COMP_H

#include <stdint.h>

#include "sh2000/comp.h"

struct sh2000_dsp;

struct sh2000_fw_comp {
	uint16_t stage[SH2000_COMP_MAX_WORDS];	/* a load in progress */
	uint32_t stage_words, stage_got;
	uint16_t img[2][SH2000_COMP_MAX_WORDS];	/* the sets */
	struct sh2000_comp_index ix[2];
	uint32_t sum[2];
	int has[2];		/* set i holds tables */
	unsigned int cur;	/* the newest set; 1 - cur: the one before */
	double blend;		/* 0..1 from set 1 - cur to set cur */
	uint16_t gen;		/* switches (the status' GEN) */
	/* this cycle's correction of each axis' set-point (counts) and its
	 * velocity and acceleration (feed-forward) */
	double off[SH2000_AXES], v[SH2000_AXES], a[SH2000_AXES];
};

void sh2000_comp_boot(struct sh2000_dsp *fw);
/* COMP_* commands (enum sh2000_cmd_result; *value: a refusal's
 * SH2000_COMP_FAULT). */
uint16_t sh2000_comp_command(struct sh2000_dsp *fw, uint16_t op,
			     uint16_t param, uint32_t arg, uint32_t *value);
/* Every servo cycle, after the set-points are computed and before the
 * loops are closed: the corrections at the nominal set-points. */
void sh2000_comp_cycle(struct sh2000_dsp *fw, double T);
/* The nominal set-point of axis a whose corrected set-point is sp (both
 * in counts; the other axes at their nominal set-points): what a hold
 * that keeps the motor where it is holds. */
double sh2000_comp_nominal_at(const struct sh2000_dsp *fw, unsigned int a,
			      double sp);
/* Axis a's corrected set-point now (its nominal one plus the tables'
 * correction at the nominal set-points as they are in this cycle; the
 * last cycle's correction is stale once a set-point moved). */
double sh2000_comp_corrected(const struct sh2000_dsp *fw, unsigned int a);
/* Axis a's nominal set-point was moved from `was` by a preset, not by
 * motion: the next cycle must not see the step this made in the
 * corrections (a preset over a steep table would feed forward the
 * difference of its corrections at the two places as one cycle's
 * velocity, a kick), only what the motion changes, for every axis. */
void sh2000_comp_rebase(struct sh2000_dsp *fw, unsigned int a, double was);
/* The counter as the host sees it in the snapshot: in nominal counts
 * (the correction taken out), 28 bits. */
uint32_t sh2000_comp_nominal_counter(const struct sh2000_dsp *fw,
				     unsigned int a);

#endif /* SH2000_CARDMODEL_COMP_H */
