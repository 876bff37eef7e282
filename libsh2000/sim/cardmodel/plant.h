/* SPDX-License-Identifier: MIT */
/*
 * The machine behind the card (one axis): a linear motor driven by the
 * amplifier's voltage, the carriage's limit and home switches, and the
 * optical scale with its index marks. Only the board (board.c) and the
 * tests touch it: the firmware sees none of this, only the FPGA's
 * registers the board derives from it (board.h).
 */
#ifndef SH2000_PLANT_H
#define SH2000_PLANT_H

#include <stdint.h>

#include "sh2000/sh2000_cardsim.h"

/* One edge of the index signal crossed in a step (the first, if more). */
struct sh2000_index_edge {
	int crossed;
	int64_t mark;		/* the scale's count at the edge */
	int home;		/* the home switch was active there */
};

struct sh2000_plant {
	struct sh2000_plant_config cfg;
	double x_mm;		/* physical position */
	double v_mm_s;		/* physical velocity */
	int jammed;		/* injected: the carriage does not move */
	/* the index signal's edges in the last step, in the direction of
	 * travel: rising (into a mark), falling (out of one) */
	struct sh2000_index_edge rise, fall;
	double cache_T, cache_m, cache_e;	/* exp(-b T / m), last T, m */
	uint64_t steps;		/* periods integrated (switch chatter) */
	/* the machine's geometry: the scale's pitch error (the axis is
	 * p->axis of it) */
	const struct sh2000_geometry *geom;
	unsigned int axis;
};

void sh2000_plant_init(struct sh2000_plant *p,
		       const struct sh2000_plant_config *cfg);
/* Addition: the scale of this plant reads through g's pitch error of
 * axis `axis` (g outlives the plant; NULL: a perfect scale). */
void sh2000_plant_set_geometry(struct sh2000_plant *p,
			       const struct sh2000_geometry *g,
			       unsigned int axis);
/* Integrates `T` seconds with the amplifier's input `volts` held. */
void sh2000_plant_step(struct sh2000_plant *p, double volts, double T);
/* The same with an outside force (N, held over T) and the moving mass of
 * this step instead of the configured one: a side of a gantry, which the
 * beam pulls and whose share of the carriage changes (gantry.c). */
void sh2000_plant_step_with(struct sh2000_plant *p, double volts,
			    double force_n, double mass_kg, double T);
/* The scale's count at the carriage: floor(scale(x) * counts_per_mm),
 * scale(x) the reading with the pitch error. The FPGA
 * counts its pulses; where its counter starts is the board's business. */
int64_t sh2000_plant_scale(const struct sh2000_plant *p);
int sh2000_plant_limit_neg(const struct sh2000_plant *p);
int sh2000_plant_limit_pos(const struct sh2000_plant *p);
int sh2000_plant_home(const struct sh2000_plant *p);
/* Carriage velocity in scale counts per second (probes). */
double sh2000_plant_velocity(const struct sh2000_plant *p);

#endif /* SH2000_PLANT_H */
