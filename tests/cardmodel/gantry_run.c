// SPDX-License-Identifier: MIT
/*
 * The gantry scenario (gantry_run.h). The move is jerk-limited: its
 * acceleration rises and falls as A sin^2(pi t / Ta), so the jerk is at
 * most pi A / Ta, and it is sampled every coarse period into the records
 * both sides get, as LinuxCNC's two joints of one axis get one position.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gantry_run.h"

#define COUNTS_PER_MM	100000.0
#define TAIL_S		0.1	/* observed after the move or the fault */

struct profile {
	double dist, v, a, ta, total;
};

static void profile_init(struct profile *p, const struct gantry_move *m)
{
	p->dist = m->dist_mm;
	p->a = m->a_mm_s2;
	p->v = m->v_mm_s;
	if (2.0 * p->v * p->v / p->a > p->dist)	/* no cruise: slower */
		p->v = sqrt(p->dist * p->a / 2.0);
	p->ta = 2.0 * p->v / p->a;
	p->total = 2.0 * p->ta + (p->dist - p->v * p->ta) / p->v;
}

/* Distance covered t into the acceleration. */
static double accel_x(const struct profile *p, double t)
{
	double w = 2.0 * M_PI / p->ta;

	return 0.5 * p->a * (0.5 * t * t + (cos(w * t) - 1.0) / (w * w));
}

static double profile_x(const struct profile *p, double t)
{
	if (t <= 0.0)
		return 0.0;
	if (t >= p->total)
		return p->dist;
	if (t < p->ta)
		return accel_x(p, t);
	if (t > p->total - p->ta)
		return p->dist - accel_x(p, p->total - t);
	return accel_x(p, p->ta) + p->v * (t - p->ta);
}

/* A fresh card as the gantry: sides enabled, the shared tuning, the pair
 * coupled or not. */
static int setup(struct harness *h, const struct gantry_move *m)
{
	struct sh2000_sim_config cfg;
	struct sh2000_gantry_config g;
	const double kaff = sh2000_param_lookup(SH2000_P_KAFF)->def *
			    GR_KAFF_KG / 2.0;	/* the default is for 2 kg */
	unsigned int s, G = SH2000_AXIS_GLOBAL;
	int bad = 0;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = m->carriage_mm;
	h_init(h, &cfg);
	sh2000_gantry_config_default(&g);
	if (sh2000_fw_set_gantry(h->fw, &g))
		return -1;
	bad |= h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 0x7, NULL);
	for (s = GR_A; s <= GR_B; s++)
		bad |= h_set_f(h, s, SH2000_P_KAFF, kaff);
	bad |= h_set_i(h, G, SH2000_GP_GANTRY_PAIR, (1 << GR_A) | (1 << GR_B));
	if (m->skew_limit)
		bad |= h_set_i(h, G, SH2000_GP_GANTRY_SKEW_LIMIT, m->skew_limit);
	if (m->couple) {
		static const double def[3] = {
			GR_GANTRY_KP, GR_GANTRY_TI, GR_GANTRY_TD,
		};
		const double *k = m->gains ? m->gains : def;

		bad |= h_set_f(h, G, SH2000_GP_GANTRY_KP, k[0]);
		bad |= h_set_f(h, G, SH2000_GP_GANTRY_TI, k[1]);
		bad |= h_set_f(h, G, SH2000_GP_GANTRY_TD, k[2]);
	}
	return bad ? -1 : 0;
}

/* What one cycle shows: peaks, the skew fault's cycles. */
static void observe(struct harness *h, const struct gantry_move *m,
		    struct gantry_result *r, double *last_cmd)
{
	const struct sh2000_dsp *d = &h->fw->dsp;
	const struct sh2000_fw_axis *xa = &d->ax[GR_A], *xb = &d->ax[GR_B];
	double yaw = fabs(sh2000_fw_gantry_yaw_mm(h->fw)) * 1e3;
	double skew = fabs((xa->cmd - (double)xa->act) -
			   (xb->cmd - (double)xb->act));
	double fa = fabs(xa->cmd - (double)xa->act),
	       fb = fabs(xb->cmd - (double)xb->act);
	int32_t lim = m->skew_limit ? m->skew_limit : d->gantry.skew_limit;

	if (yaw > r->peak_yaw_um)
		r->peak_yaw_um = yaw;
	if (!(xa->faults & SH2000_AXIS_FAULT_SKEW) && skew > r->peak_skew_counts)
		r->peak_skew_counts = skew;
	if ((fa > fb ? fa : fb) / COUNTS_PER_MM * 1e3 > r->peak_ferr_um &&
	    !r->fault_cycle)
		r->peak_ferr_um = (fa > fb ? fa : fb) / COUNTS_PER_MM * 1e3;
	if (!r->cross_cycle && llabs(xa->act - xb->act) > lim)
		r->cross_cycle = d->cycle;
	if (!r->fault_cycle && (xa->faults & SH2000_AXIS_FAULT_SKEW) &&
	    (xb->faults & SH2000_AXIS_FAULT_SKEW))
		r->fault_cycle = d->cycle;
	if (xa->cmd != last_cmd[0] || xb->cmd != last_cmd[1])
		r->held_cycle = d->cycle;
	last_cmd[0] = xa->cmd;
	last_cmd[1] = xb->cmd;
}

/* After the fault: where side a, which was moving, first comes to rest
 * (its velocity crosses zero) and how far it went from the fault. */
static void free_side(struct harness *h, struct gantry_result *r, double Ts)
{
	const struct sh2000_plant *p = sh2000_board_plant(h->fw->hw, GR_A);

	if (r->free_side_stop_ms > 0.0)
		return;
	if (h->fw->dsp.cycle == r->fault_cycle) {
		r->fault_x_mm = p->x_mm;
		r->fault_v_mm_s = p->v_mm_s;
		return;
	}
	if (p->v_mm_s * r->fault_v_mm_s <= 0.0) {
		r->free_side_stop_ms =
			(double)(h->fw->dsp.cycle - r->fault_cycle) * Ts * 1e3;
		r->free_side_travel_mm = fabs(p->x_mm - r->fault_x_mm);
	}
}

int gantry_run(const struct gantry_move *m, struct gantry_result *r)
{
	static struct harness h;	/* its RAM is large */
	struct profile p;
	double Tc, Ts, last_cmd[2] = { 0.0, 0.0 }, end_s = -1.0;
	unsigned int n, next = 0, k;
	int jammed = 0;

	memset(r, 0, sizeof(*r));
	profile_init(&p, m);
	r->jerk_mm_s3 = M_PI * p.a / p.ta;
	if (setup(&h, m)) {
		h_fini(&h);
		return -1;
	}
	Tc = sh2000_param_lookup(SH2000_GP_COARSE_PERIOD_US)->def * 1e-6;
	Ts = (double)sh2000_fw_servo_period_ns(h.fw) * 1e-9;
	n = (unsigned int)ceil(p.total / Tc) + 1u;
	for (k = 0;; k++) {
		double t = k * Ts;

		while (next < n && h_word(&h, SH2000_W_STATE) != SH2000_STATE_FAULT) {
			int32_t pos[SH2000_AXES] = { 0, 0, 0, 0 };

			pos[GR_A] = pos[GR_B] = (int32_t)lrint(
				profile_x(&p, next * Tc) * COUNTS_PER_MM);
			if (h_push(&h, pos, (uint16_t)next,
				   next + 1 == n ? SH2000_REC_F_END : 0))
				break;
			next++;
		}
		if (m->jam_at_s >= 0.0 && !jammed && t >= m->jam_at_s) {
			sh2000_fw_inject(h.fw, SH2000_INJECT_JAM, GR_B, 1);
			jammed = 1;
		}
		h_cycles(&h, 1);
		observe(&h, m, r, last_cmd);
		if (r->fault_cycle)
			free_side(&h, r, Ts);
		if (end_s < 0.0 && ((next == n && h_word(&h, SH2000_W_STATE) ==
					     SH2000_STATE_IDLE) ||
				    h_word(&h, SH2000_W_STATE) == SH2000_STATE_FAULT))
			end_s = t;
		if ((end_s >= 0.0 && t > end_s + TAIL_S) || t > p.total + 5.0)
			break;
	}
	r->cycles = k + 1;
	h_fini(&h);
	return 0;
}

const char *gantry_jam_text(const struct gantry_result *r, char *buf,
			    unsigned int len)
{
	snprintf(buf, len,
		 "skew limit crossed in cycle %llu, SKEW latched in %llu, both "
		 "set-points held from %llu; side a from %.1f mm/s to rest in "
		 "%.1f ms, %.3f mm",
		 (unsigned long long)r->cross_cycle,
		 (unsigned long long)r->fault_cycle,
		 (unsigned long long)r->held_cycle, r->fault_v_mm_s,
		 r->free_side_stop_ms, r->free_side_travel_mm);
	return buf;
}

int gantry_home_card(struct harness *h, const struct sh2000_sim_config *cfg,
		     int32_t square)
{
	const unsigned int G = SH2000_AXIS_GLOBAL;
	struct sh2000_gantry_config g;
	int bad = 0;

	h_init(h, cfg);
	sh2000_gantry_config_default(&g);
	if (sh2000_fw_set_gantry(h->fw, &g))
		return -1;
	bad |= h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 0x7, NULL);
	bad |= h_set_i(h, G, SH2000_GP_GANTRY_PAIR, (1 << GR_A) | (1 << GR_B));
	bad |= h_set_i(h, G, SH2000_GP_GANTRY_SQUARE, square);
	bad |= h_set_f(h, G, SH2000_GP_GANTRY_KP, GR_GANTRY_KP);
	return bad ? -1 : 0;
}
