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
}

static double clamp(double x, double lim)
{
	if (x > lim)
		return lim;
	if (x < -lim)
		return -lim;
	return x;
}

int16_t sh2000_pid_step(struct sh2000_pid *p, const struct sh2000_pid_gains *g,
			double e, double v, double a, double tau)
{
	double lim = (double)g->dac_limit;
	double du, out;

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
	out = clamp(p->u + p->ff, lim);
	/* The DAC7744 takes 16-bit codes: round to the nearest. */
	return (int16_t)lrint(out);
}
