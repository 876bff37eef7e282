// SPDX-License-Identifier: MIT
/*
 * One axis of the machine: a linear motor (mass m, viscous friction b,
 * force constant k incl. the amplifier) driven by the DAC voltage,
 *   m dv/dt = k V - b v,
 * integrated exactly over a period with V held (zero-order hold); limit and
 * home switches at fixed positions; an optical scale with index marks
 * every index_period_mm, each of a width (its signal's rising and falling
 * edges). What the FPGA makes of the scale's pulses (the
 * 28-bit counter, the index latch) is the board's (board.c).
 */
#include <math.h>

#include "plant.h"

void sh2000_sim_config_default(struct sh2000_sim_config *cfg)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_plant_config *p = &cfg->axis[a];

		p->mass_kg = 2.0;
		p->friction_ns_per_m = 20.0;
		p->force_n_per_v = 20.0;
		p->counts_per_mm = 100000.0;
		p->limit_neg_mm = -5.0;
		p->limit_pos_mm = 605.0;
		p->home_mm = 0.0;
		p->index_period_mm = 1.0;
		p->start_mm = 300.0;
		p->home_bounce_mm = 0.0;
		p->index_pos_mm = 0.0;
		p->index_width_mm = 0.0;
	}
}

/* What the scale reads at carriage position x (mm). */
static double scale_mm(const struct sh2000_plant *p, double x_mm)
{
	return p->geom ? sh2000_geometry_scale(p->geom, p->axis, x_mm) : x_mm;
}

/* The count of scale reading s (mm). */
static int64_t counts_at(const struct sh2000_plant *p, double s_mm)
{
	return (int64_t)floor(s_mm * p->cfg.counts_per_mm);
}

void sh2000_plant_set_geometry(struct sh2000_plant *p,
			       const struct sh2000_geometry *g,
			       unsigned int axis)
{
	p->geom = g;
	p->axis = axis;
}

void sh2000_plant_init(struct sh2000_plant *p,
		       const struct sh2000_plant_config *cfg)
{
	p->cfg = *cfg;
	p->x_mm = cfg->start_mm;
	p->v_mm_s = 0.0;
	p->jammed = 0;
	p->rise.crossed = 0;
	p->fall.crossed = 0;
	p->cache_T = -1.0;
	p->cache_m = -1.0;
	p->cache_e = 0.0;
	p->steps = 0;
	p->geom = NULL;
	p->axis = 0;
}

/* The home switch at x, without its chatter (what the FPGA's mask input
 * shows at an index edge). A mark placed at the switch's point is on the
 * switch: the carriage's place at the edge is interpolated within the
 * step, and its last bits of rounding (a picometre allowed) must not
 * decide which side of the switch a mark at its point lies. */
#define HOME_AT_ROUNDING_MM	1e-9
static int home_at(const struct sh2000_plant *p, double x_mm)
{
	return x_mm <= p->cfg.home_mm + HOME_AT_ROUNDING_MM;
}

/* Edge positions pos + k * per + off that lie in (lo, hi]: the first one
 * met going from s0 towards s1 (*at), 1 if there is one. All three are
 * scale readings: the marks are graduations of the scale. */
static int first_edge(const struct sh2000_plant *p, double off, double s0,
		      double s1, double *at)
{
	double per = p->cfg.index_period_mm, base = p->cfg.index_pos_mm + off;
	double k;

	if (s1 > s0) {
		k = floor((s0 - base) / per) + 1.0;	/* first above s0 */
		*at = base + k * per;
		return *at <= s1;
	}
	k = ceil((s0 - base) / per) - 1.0;		/* first below s0 */
	*at = base + k * per;
	return *at >= s1;
}

/* An edge met in this step: its count, and the home switch where the
 * carriage was when the scale read the edge (the step is short: the
 * carriage moved linearly with the reading within it). */
static void edge(struct sh2000_plant *p, struct sh2000_index_edge *e,
		 double off, double x0, const double s[2])
{
	double at;

	if (!first_edge(p, off, s[0], s[1], &at))
		return;
	e->crossed = 1;
	e->mark = counts_at(p, at);
	e->home = home_at(p, x0 + (p->x_mm - x0) * (at - s[0]) / (s[1] - s[0]));
}

/* The index signal's edges between x0 and the new x: going up, a mark
 * rises at its start and falls at its end; going down the other way. */
static void find_index(struct sh2000_plant *p, double x0)
{
	double w = p->cfg.index_width_mm > 0.0 ? p->cfg.index_width_mm : 0.0;
	double s[2] = { scale_mm(p, x0), scale_mm(p, p->x_mm) };
	int up = s[1] > s[0];

	if (p->cfg.index_period_mm <= 0.0 || s[1] == s[0])
		return;
	edge(p, &p->rise, up ? 0.0 : w, x0, s);
	edge(p, &p->fall, up ? w : 0.0, x0, s);
}

void sh2000_plant_step(struct sh2000_plant *p, double volts, double T)
{
	sh2000_plant_step_with(p, volts, 0.0, p->cfg.mass_kg, T);
}

void sh2000_plant_step_with(struct sh2000_plant *p, double volts,
			    double force_n, double mass_kg, double T)
{
	double m = mass_kg, b = p->cfg.friction_ns_per_m;
	double F = p->cfg.force_n_per_v * volts + force_n;
	double v0 = p->v_mm_s * 1e-3, x0 = p->x_mm, v1, dx;

	p->rise.crossed = 0;
	p->fall.crossed = 0;
	p->steps++;
	if (p->jammed) {
		p->v_mm_s = 0.0;
		return;
	}
	if (b > 0.0) {
		double vss = F / b;

		if (T != p->cache_T || m != p->cache_m) {
			p->cache_T = T;
			p->cache_m = m;
			p->cache_e = exp(-b * T / m);
		}
		v1 = vss + (v0 - vss) * p->cache_e;
		dx = vss * T + (v0 - vss) * (m / b) * (1.0 - p->cache_e);
	} else {
		v1 = v0 + F / m * T;
		dx = v0 * T + 0.5 * F / m * T * T;
	}
	p->x_mm = x0 + dx * 1e3;
	p->v_mm_s = v1 * 1e3;
	find_index(p, x0);
}

int64_t sh2000_plant_scale(const struct sh2000_plant *p)
{
	return counts_at(p, scale_mm(p, p->x_mm));
}

int sh2000_plant_limit_neg(const struct sh2000_plant *p)
{
	return p->x_mm <= p->cfg.limit_neg_mm;
}

int sh2000_plant_limit_pos(const struct sh2000_plant *p)
{
	return p->x_mm >= p->cfg.limit_pos_mm;
}

int sh2000_plant_home(const struct sh2000_plant *p)
{
	/* a mechanical switch chatters near its point: what debounce is for */
	if (fabs(p->x_mm - p->cfg.home_mm) < p->cfg.home_bounce_mm)
		return (p->steps / 3u) & 1u;
	return p->x_mm <= p->cfg.home_mm;
}

double sh2000_plant_velocity(const struct sh2000_plant *p)
{
	return p->v_mm_s * p->cfg.counts_per_mm;
}
