// SPDX-License-Identifier: MIT
/*
 * The gantry's mechanics. Each side is its axis' linear motor (plant.c)
 * carrying half the beam and its share of the carriage: with s the
 * carriage's place along the beam (0 at side a, 1 at side b),
 *   m_a = m_motor + m_beam / 2 + (1 - s) m_carriage,  m_b likewise with s;
 * the joints between beam and sides give the yaw (y_a - y_b) a spring k
 * and a damper c, so side a feels -k (y_a - y_b) - c (v_a - v_b) and side
 * b the opposite. The coupling force changes within a servo period, so
 * the period is cut into steps of at most GANTRY_STEP_S, each integrated
 * exactly (plant.c) with the force of its start held: the yaw mode of the
 * defaults (tens of Hz) is resolved in thousands of steps per swing.
 */
#include <math.h>

#include "gantry.h"

#define GANTRY_STEP_S	10e-6

void sh2000_gantry_config_default(struct sh2000_gantry_config *g)
{
	g->side_a = 1;
	g->side_b = 2;
	g->carriage_axis = 0;
	g->beam_kg = 6.0;
	g->carriage_kg = 8.0;
	g->span_mm = 600.0;
	g->carriage_at0_mm = 0.0;
	g->stiffness_n_per_m = 5e4;
	g->damping_ns_per_m = 20.0;
}

int sh2000_gantry_check(const struct sh2000_gantry_config *c)
{
	if (c->side_a >= SH2000_AXES || c->side_b >= SH2000_AXES ||
	    c->side_a == c->side_b)
		return -22;
	if (c->carriage_axis >= (int)SH2000_AXES ||
	    c->carriage_axis == (int)c->side_a ||
	    c->carriage_axis == (int)c->side_b)
		return -22;
	if (!(c->span_mm > 0.0) || !(c->beam_kg >= 0.0) ||
	    !(c->carriage_kg >= 0.0) || !(c->stiffness_n_per_m >= 0.0) ||
	    !(c->damping_ns_per_m >= 0.0) || !isfinite(c->carriage_at0_mm))
		return -22;
	return 0;
}

int sh2000_gantry_side(const struct sh2000_gantry *g, unsigned int axis)
{
	return g->on && (axis == g->cfg.side_a || axis == g->cfg.side_b);
}

/* The carriage's share on side b, 0..1. */
static double share_b(const struct sh2000_gantry_config *c,
		      const struct sh2000_plant *carriage)
{
	double x = c->carriage_at0_mm + (carriage ? carriage->x_mm : 0.0);
	double s = x / c->span_mm;

	return s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
}

/* plant_step clears the edges of the step before: keep the first rising
 * and the first falling one of the period, as the FPGA's latch sees them. */
static void keep_edges(const struct sh2000_plant *p,
		       struct sh2000_index_edge *rise,
		       struct sh2000_index_edge *fall)
{
	if (p->rise.crossed && !rise->crossed)
		*rise = p->rise;
	if (p->fall.crossed && !fall->crossed)
		*fall = p->fall;
}

void sh2000_gantry_step(const struct sh2000_gantry *g, struct sh2000_plant *pa,
			struct sh2000_plant *pb,
			const struct sh2000_plant *carriage, double va,
			double vb, double T)
{
	const struct sh2000_gantry_config *c = &g->cfg;
	double s = share_b(c, carriage);
	double ma = pa->cfg.mass_kg + 0.5 * c->beam_kg + (1.0 - s) * c->carriage_kg;
	double mb = pb->cfg.mass_kg + 0.5 * c->beam_kg + s * c->carriage_kg;
	unsigned int n = (unsigned int)ceil(T / GANTRY_STEP_S - 1e-9), i;
	struct sh2000_index_edge ra = { 0 }, fa = { 0 }, rb = { 0 }, fb = { 0 };
	double dt;

	if (n == 0)
		n = 1;
	dt = T / n;
	for (i = 0; i < n; i++) {
		double f = -c->stiffness_n_per_m * (pa->x_mm - pb->x_mm) * 1e-3 -
			   c->damping_ns_per_m * (pa->v_mm_s - pb->v_mm_s) * 1e-3;

		sh2000_plant_step_with(pa, va, f, ma, dt);
		sh2000_plant_step_with(pb, vb, -f, mb, dt);
		keep_edges(pa, &ra, &fa);
		keep_edges(pb, &rb, &fb);
	}
	/* one period for the switches' chatter (plant.c), as an axis alone */
	pa->steps -= n - 1u;
	pb->steps -= n - 1u;
	pa->rise = ra;
	pa->fall = fa;
	pb->rise = rb;
	pb->fall = fb;
}
