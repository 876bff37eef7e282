// SPDX-License-Identifier: MIT
/*
 * One axis of the machine: a linear motor (mass m, viscous friction b,
 * force constant k incl. the amplifier) driven by the DAC voltage,
 *   m dv/dt = k V - b v,
 * integrated exactly over a servo period with V held (zero-order hold);
 * limit and home switches at fixed positions; an optical scale whose
 * counts go into the FPGA's 28-bit counter, which wraps; index marks every
 * index_period_mm whose crossing latches the counter (as the FPGA would).
 */
#include <math.h>

#include "cardmodel.h"

double sh2000_dac_volts_per_code(unsigned int range)
{
	switch (range) {
	case SH2000_DAC_0_5V:
		return 5.0 / 65536.0;
	case SH2000_DAC_0_10V:
		return 10.0 / 65536.0;
	case SH2000_DAC_PM5V:
		return 5.0 / 32768.0;
	default:
		return 10.0 / 32768.0;
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
	/* An incremental scale: the counter powers up at 0. */
	p->enc_offset = -counts_at(p, cfg->start_mm);
	p->jammed = 0;
	p->force_limit = 0;
	p->index_seen = 0;
	p->index_latch = 0;
	p->cache_T = -1.0;
	p->cache_e = 0.0;
	p->steps = 0;
}

static uint32_t wrap(int64_t c)
{
	return (uint32_t)((uint64_t)c & SH2000_COUNTER_MASK);
}

void sh2000_plant_step(struct sh2000_plant *p, int16_t dac, unsigned int range,
		       double T)
{
	double m = p->cfg.mass_kg, b = p->cfg.friction_ns_per_m;
	double F = p->cfg.force_n_per_v * dac * sh2000_dac_volts_per_code(range);
	double v0 = p->v_mm_s * 1e-3, x0 = p->x_mm, v1, dx;
	double per = p->cfg.index_period_mm;

	p->index_seen = 0;
	p->steps++;
	if (p->jammed) {
		p->v_mm_s = 0.0;
		return;
	}
	if (b > 0.0) {
		double vss = F / b;

		if (T != p->cache_T) {
			p->cache_T = T;
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
	if (per > 0.0) {
		double k0 = floor(x0 / per), k1 = floor(p->x_mm / per);

		if (k0 != k1) {
			double mark = (k1 > k0 ? k1 : k0) * per;

			p->index_seen = 1;
			p->index_latch = wrap(counts_at(p, mark) + p->enc_offset);
		}
	}
}

uint32_t sh2000_plant_counter(const struct sh2000_plant *p)
{
	return wrap(counts_at(p, p->x_mm) + p->enc_offset);
}

void sh2000_plant_preset(struct sh2000_plant *p, uint32_t value)
{
	p->enc_offset = (int64_t)(value & SH2000_COUNTER_MASK) -
			counts_at(p, p->x_mm);
}

int sh2000_plant_limit_neg(const struct sh2000_plant *p)
{
	return (p->force_limit & 1) || p->x_mm <= p->cfg.limit_neg_mm;
}

int sh2000_plant_limit_pos(const struct sh2000_plant *p)
{
	return (p->force_limit & 2) || p->x_mm >= p->cfg.limit_pos_mm;
}

int sh2000_plant_home(const struct sh2000_plant *p)
{
	/* a mechanical switch chatters near its point: what debounce is for */
	if (fabs(p->x_mm - p->cfg.home_mm) < p->cfg.home_bounce_mm)
		return (p->steps / 3u) & 1u;
	return p->x_mm <= p->cfg.home_mm;
}
