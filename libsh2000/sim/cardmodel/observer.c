// SPDX-License-Identifier: MIT
/*
 * The servo's position finer than a count, as a DSP servo estimates it:
 * an observer that runs the axis' model (the motor whose exact inverse
 * the feed-forward gains are: a = (DAC - KVFF v) / KAFF, counts/s^2 per
 * code) forward over every servo period with the DAC code it held, and
 * keeps the estimate within the count the counter reads (the counter is
 * the floor of the scale's reading: the reading is in [c, c + 1)).
 *
 * Why: the counter alone tells the loop only which count the carriage is
 * in. Moving, the set-point's fraction then comes and goes with every
 * count's edge (a derivative kick of Kp Td/tau per count); at rest the
 * loop can only hold the reading on a count's edge, up to half a count
 * from where a compensation table's corrected set-point puts the tool.
 * With the estimate the loop closes on the reading itself: the carriage
 * at S + 1/2, the middle of the set-point S's count as the calibration
 * measures it, moving and at rest.
 *
 * Without a model (KVFF or KAFF 0, or a gantry pair's sides, which the
 * beam couples) the loop closes on the counter as before.
 */
#include <math.h>
#include <string.h>

#include "cardmodel.h"

/* How far into the count the estimate is kept (a count's edge itself
 * belongs to the count above). */
#define EDGE	1e-6
/* The scale's rate against the model's (track_rate): the model's travel
 * summed with this weight per period (about the last 100 periods: 0.4 mm
 * at 40 mm/s, short against a pitch error's period of some mm), at least
 * this many counts, and only from steps of at least RATE_STEP counts. */
#define RATE_DECAY	0.99
#define RATE_STEP	10.0
#define RATE_MIN	2e4

void sh2000_obs_reset(struct sh2000_obs *o)
{
	memset(o, 0, sizeof(*o));
	o->rate = 1.0;
}

/*
 * The scale's counts per count of the model's travel: the model moves the
 * carriage, the scale reads it with its pitch error (a slope of up to a
 * few 1e-4 locally on the default machine: 0.1 count a period at 40
 * mm/s). Every correction d the counter forces on the estimate is that
 * much travel the rate missed over the model's recent travel (sum_m): the
 * rate takes it, so the estimate stops drifting between corrections and
 * a stop ends where the count's edges last put it.
 */
static void track_rate(struct sh2000_obs *o, double d)
{
	if (fabs(o->dm) < RATE_STEP)
		return;		/* creeping: the rate is the last one's */
	o->sum_m = RATE_DECAY * o->sum_m + fabs(o->dm);
	o->rate += (o->dm < 0.0 ? -d : d) / fmax(o->sum_m, RATE_MIN);
}

static int has_model(const struct sh2000_fw_params *p)
{
	return p->kvff > 0.0 && p->kaff > 0.0;
}

double sh2000_obs_error(struct sh2000_fw_axis *ax, double sp, int model,
			double T)
{
	struct sh2000_obs *o = &ax->obs;
	double c = (double)ax->act, lo = c + EDGE, hi = c + 1.0 - EDGE, d;

	if (!model || !has_model(&ax->prm)) {
		sh2000_obs_reset(o);
		return sp - c;
	}
	if (!o->on) {
		/* the first cycle: the middle of the count, the counter's
		 * own velocity */
		o->on = 1;
		o->x = c + 0.5;
		o->v = (double)ax->delta / T;
	} else if (o->x < c - 1.0 || o->x >= c + 2.0) {
		/* the counter jumped (a glitch): the scale's fraction did
		 * not, the estimate jumps with it */
		o->x += c - floor(o->x);
	}
	d = fmin(hi, fmax(lo, o->x)) - o->x;
	o->x += d;
	track_rate(o, d);
	return sp + 0.5 - o->x;
}

void sh2000_obs_predict(struct sh2000_fw_axis *ax, double T)
{
	struct sh2000_obs *o = &ax->obs;
	double alpha, vss, e;

	if (!o->on)
		return;
	/* m dv/dt = k V - b v with V held: b/m = KVFF/KAFF, and the speed
	 * V holds against friction is DAC/KVFF (the motor's exact step over
	 * the period, in the model's counts; the scale's are rate times) */
	alpha = ax->prm.kvff / ax->prm.kaff;
	vss = (double)ax->dac / ax->prm.kvff;
	if (alpha * T != o->at || o->decay == 0.0) {
		o->at = alpha * T;
		o->decay = exp(-o->at);
	}
	e = o->decay;
	o->dm = vss * T + (o->v - vss) * (1.0 - e) / alpha;
	o->x += o->rate * o->dm;
	o->v = vss + (o->v - vss) * e;
}
