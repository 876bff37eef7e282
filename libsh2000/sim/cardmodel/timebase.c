// SPDX-License-Identifier: MIT
/*
 * The card's time base (protocol 1.1, docs/protocol.md section 8.4): the
 * rate sigma (0..1) at which the firmware consumes coarse periods. A feed
 * hold is sigma -> 0, a resume sigma -> 1, an override a target between:
 * the geometry is the records' whatever sigma does, so the motion never
 * leaves the path, and the change starts in the servo cycle after the
 * host's request lands, however many records are queued.
 *
 * sigma follows its target with a jerk-limited ramp: its second
 * derivative is at most 4 / ramp^2 (a full 0..1 ramp takes at least
 * TIME_RAMP_MS), and its first derivative is at most what each axis'
 * acceleration leaves: sigma' |v| + sigma^2 |a| <= 0.95 amax, with v and a
 * the axis' set-point velocity and acceleration at full rate.
 */
#include <math.h>

#include "cardmodel.h"

#define TB_AMAX_SHARE 0.95

/* The largest |sigma'| the axes allow now. */
static double rate_limit(const struct sh2000_dsp *fw)
{
	double lim = INFINITY, s2 = fw->tb_sigma * fw->tb_sigma;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_fw_axis *ax = &fw->ax[a];
		double room = TB_AMAX_SHARE * ax->prm.amax -
			      s2 * fabs(fw->tb_a[a]);

		if (!sh2000_axis_enabled(ax) || fabs(fw->tb_v[a]) < 1e-9)
			continue;
		lim = fmin(lim, fmax(room, 0.0) / fabs(fw->tb_v[a]));
	}
	return lim;
}

void sh2000_tb_step(struct sh2000_dsp *fw, double T)
{
	double target = (double)fw->time_scale / SH2000_TIME_SCALE_FULL;
	double ramp = (double)fw->time_ramp_ms * 1e-3;
	double J = 4.0 / (ramp * ramp), A = rate_limit(fw);
	double d = target - fw->tb_sigma, want, r = fw->tb_rate;

	if (d == 0.0 && r == 0.0)
		return;
	/* the fastest rate from which the ramp still lands on the target */
	want = copysign(sqrt(2.0 * J * fabs(d)), d);
	want = fmax(-A, fmin(A, want));
	r += fmax(-J * T, fmin(J * T, want - r));
	fw->tb_sigma += r * T;
	/* on (or past) the target: there */
	if ((d >= 0.0 && fw->tb_sigma >= target) ||
	    (d <= 0.0 && fw->tb_sigma <= target)) {
		fw->tb_sigma = target;
		r = 0.0;
	}
	fw->tb_sigma = fmin(fmax(fw->tb_sigma, 0.0), 1.0);
	fw->tb_rate = r;
}
