// SPDX-License-Identifier: MIT
/*
 * The paper's incremental PID,
 *   u(k) = u(k-1) + Kp{ e(k)-e(k-1) + (tau/Ti) e(k)
 *                      + (Td/tau)[e(k)-2e(k-1)+e(k-2)] },
 * plus velocity and acceleration feed-forward added outside the
 * accumulator (so changing the set-point's speed does not wind it up).
 * The accumulated u is clamped to the DAC limit: that is the anti-windup.
 */
#include <math.h>

#include "cardmodel.h"

void sh2000_pid_reset(struct sh2000_pid *p)
{
	p->u = 0.0;
	p->e1 = 0.0;
	p->e2 = 0.0;
	p->p = p->i = p->d = p->ff = 0.0;
	p->carry = 0.0;
}

static double clamp(double x, double lim)
{
	if (x > lim)
		return lim;
	if (x < -lim)
		return -lim;
	return x;
}

/* How near a whole count a corrected set-point is on it (counts, 10 fm):
 * far above the rounding left in a set-point the tables' correction put
 * on a count (a hold's or a homing's inversion, some 1e-12 count; a
 * double's last bit at 2^28 counts is 6e-8), far below any fraction a
 * table means. */
#define WHOLE_COUNT	1e-6

/*
 * The error the loop closes on. Moving, or further than a count: e. At
 * rest within a count of a set-point S between two counts (a compensation
 * table's correction puts it there), the counter, the floor of the scale,
 * only says on which side of the count's edge ceil(S) the carriage is;
 * e itself is S's fraction on one side and the fraction less one on the
 * other, so the integral sums the fraction, not where the carriage is:
 * it creeps through a count for a fraction near 0 or 1 and hunts over
 * two. Half a count either side of the edge instead: the loop holds the
 * reading on ceil(S), the same way whatever the fraction. A set-point on
 * a whole count (no table, or a hold or homing the tables' correction put
 * on the count, to its rounding) rests anywhere in its count, without
 * hunting: that rounding taken for a fraction held the carriage on the
 * count's edge above (S a hair over the count) or below, a count off.
 */
static double at_rest(double e, double v, double a)
{
	double n = nearbyint(e);

	if (v != 0.0 || a != 0.0 || fabs(e) > 1.0)
		return e;
	if (fabs(e - n) <= WHOLE_COUNT)
		return n;
	return ceil(e) - 0.5;
}

/* The PID and feed-forward, unrounded, within the DAC's limit. */
static double pid_out(struct sh2000_pid *p, const struct sh2000_pid_gains *g,
		      double e, double v, double a, double tau)
{
	double lim = (double)g->dac_limit;
	double du;

	du = (e - p->e1) + (g->td / tau) * (e - 2.0 * p->e1 + p->e2);
	if (g->ti > 0.0)
		du += (tau / g->ti) * e;
	p->u = clamp(p->u + g->kp * du, lim);
	/* The positional form's terms, for data gathering: summed from a
	 * reset, u = Kp e + Kp Td/tau (e - e1) + the integral; whatever the
	 * clamp took off stays in the integral's share. */
	p->p = g->kp * e;
	p->d = g->kp * (g->td / tau) * (e - p->e1);
	p->i = p->u - p->p - p->d;
	p->ff = g->kvff * v + g->kaff * a;
	p->e2 = p->e1;
	p->e1 = e;
	return clamp(p->u + p->ff, lim);
}

int16_t sh2000_pid_step(struct sh2000_pid *p, const struct sh2000_pid_gains *g,
			double e, double v, double a, double tau)
{
	/* The DAC7744 takes 16-bit codes: round to the nearest. */
	p->carry = 0.0;
	return (int16_t)lrint(pid_out(p, g, at_rest(e, v, a), v, a, tau));
}

/*
 * On the observer's error the loop can hold the carriage finer than a
 * count, but one DAC code held is 0.3 mm/s against the default axis'
 * friction: rounded to the nearest code, the loop's output below a code
 * is lost and the carriage hunts over a count or two at rest. So the
 * rounding's remainder is carried into the next cycle (first-order noise
 * shaping, as a DSP drives a DAC finer than its step): the codes average
 * to the loop's output, and one code more or less for one cycle moves the
 * carriage 0.002 count.
 */
int16_t sh2000_pid_step_fine(struct sh2000_pid *p,
			     const struct sh2000_pid_gains *g, double e,
			     double v, double a, double tau)
{
	double lim = (double)g->dac_limit;
	double out = pid_out(p, g, e, v, a, tau) + p->carry, code;

	code = clamp(nearbyint(out), lim);
	p->carry = fabs(out - code) < 1.0 ? out - code : 0.0;
	return (int16_t)code;
}
