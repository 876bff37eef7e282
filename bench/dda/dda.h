/* SPDX-License-Identifier: MIT */
/*
 * The DDA interpolator of the DDA paper [R3] (docs/references.md), as the
 * baseline the planner is measured against in tests and benchmarks. It is
 * no part of any library's API: coarse points plus the card's B-spline
 * fine interpolation replace it on this card.
 */
#ifndef SH2000_DDA_H
#define SH2000_DDA_H

#include <stdint.h>

struct sh2000_dda_config {
	unsigned int bits;	/* accumulator width, 2..31 */
	int half_load;		/* preset remainders to half capacity */
	int normalize;		/* left-shift integrands until the largest
				 * has its top bit set */
};

struct sh2000_dda_result {
	uint64_t iterations;	/* accumulation cycles */
	uint64_t pulses[3];	/* pulses per axis */
	uint64_t max_gap;	/* longest run of cycles without any pulse */
	int32_t end[3];		/* where the pulses led */
};

/* Called for every cycle that produced at least one pulse: the position
 * after it and the mask of axes that stepped. */
typedef void (*sh2000_dda_step_fn)(void *ctx, const int32_t pos[3],
				   unsigned int mask);

/* Line in up to 3 axes, integer counts. -EINVAL if a delta does not fit. */
int sh2000_dda_line(const struct sh2000_dda_config *cfg,
		    const int32_t start[3], const int32_t end[3],
		    sh2000_dda_step_fn fn, void *ctx,
		    struct sh2000_dda_result *res);
/* Arc in 2 axes around an integer centre; start and end at the same
 * rounded radius; start == end is a full circle. */
int sh2000_dda_arc(const struct sh2000_dda_config *cfg,
		   const int32_t centre[2], const int32_t start[2],
		   const int32_t end[2], int ccw,
		   sh2000_dda_step_fn fn, void *ctx,
		   struct sh2000_dda_result *res);

#endif /* SH2000_DDA_H */
