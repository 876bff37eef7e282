// SPDX-License-Identifier: MIT
/*
 * One axis of the machine: a linear motor (mass m, viscous friction b,
 * force constant k incl. the amplifier) driven by the DAC voltage,
 *   m dv/dt = k V - b v,
 * integrated exactly over a period with V held (zero-order hold); limit and
 * home switches at fixed positions; an optical scale with index marks
 * every index_period_mm. What the FPGA makes of the scale's pulses (the
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
	}
}

static int64_t counts_at(const struct sh2000_plant *p, double x_mm)
{
	return (int64_t)floor(x_mm * p->cfg.counts_per_mm);
}

void sh2000_plant_init(struct sh2000_plant *p,
		       const struct sh2000_plant_config *cfg)
{
	p->cfg = *cfg;
	p->x_mm = cfg->start_mm;
	p->v_mm_s = 0.0;
	p->jammed = 0;
	p->index_crossed = 0;
	p->index_mark = 0;
	p->cache_T = -1.0;
	p->cache_m = -1.0;
	p->cache_e = 0.0;
	p->steps = 0;
}

/* Did the carriage pass an index mark between x0 and the new x? */
static void find_index(struct sh2000_plant *p, double x0)
{
	double per = p->cfg.index_period_mm, k0, k1;

	if (per <= 0.0)
		return;
	k0 = floor(x0 / per);
	k1 = floor(p->x_mm / per);
	if (k0 != k1) {
		p->index_crossed = 1;
		p->index_mark = counts_at(p, (k1 > k0 ? k1 : k0) * per);
	}
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

	p->index_crossed = 0;
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
	return counts_at(p, p->x_mm);
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
