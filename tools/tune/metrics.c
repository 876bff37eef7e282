/* SPDX-License-Identifier: MIT */
/*
 * The figures of a step response: rise time (10 % to 90 % of the step,
 * crossings interpolated between samples), overshoot beyond the end,
 * settling time to TUNE_SETTLE_COUNTS (staying in the band to the end,
 * for at least a fifth of the trace), peak following error and DAC code.
 * Times count from the step's first set-point change (t = 0 in the trace).
 */
#include <math.h>

#include "tune.h"

/* Share of the trace after the step a response must stay in the band. */
#define SETTLED_SHARE 0.2

/* Time the encoder first reaches fraction f of the step (from t >= 0),
 * interpolated; NAN if never. */
static double crossing(const struct tune_trace *tr, double f)
{
	double dir = tr->end > tr->start ? 1.0 : -1.0;
	double level = (tr->start + f * (tr->end - tr->start)) * dir;

	for (size_t i = 1; i < tr->n; i++) {
		double a = tr->enc[i - 1] * dir, b = tr->enc[i] * dir;

		if (tr->t[i] < 0 || b < level)
			continue;
		if (a >= level || tr->t[i - 1] < 0)
			return tr->t[i];
		return tr->t[i - 1] + (level - a) / (b - a) *
					      (tr->t[i] - tr->t[i - 1]);
	}
	return NAN;
}

int tune_metrics(const struct tune_trace *tr, struct tune_metrics *m)
{
	double dir = tr->end > tr->start ? 1.0 : -1.0;
	double t10 = crossing(tr, 0.1), t90 = crossing(tr, 0.9);
	size_t last_out = 0;
	int out_seen = 0;

	m->overshoot = 0;
	m->peak_ferr = 0;
	m->peak_dac = 0;
	for (size_t i = 0; i < tr->n; i++) {
		double beyond = (tr->enc[i] - tr->end) * dir;

		if (beyond > m->overshoot)
			m->overshoot = beyond;
		if (fabs(tr->sp[i] - tr->enc[i]) > m->peak_ferr)
			m->peak_ferr = fabs(tr->sp[i] - tr->enc[i]);
		if (fabs(tr->dac[i]) > m->peak_dac)
			m->peak_dac = fabs(tr->dac[i]);
		if (tr->t[i] >= 0 &&
		    fabs(tr->enc[i] - tr->end) > TUNE_SETTLE_COUNTS) {
			last_out = i;
			out_seen = 1;
		}
	}
	m->overshoot_pct = 100.0 * m->overshoot / fabs(tr->end - tr->start);
	/* settled: in the band from the sample after the last one outside
	 * to the end, and for at least a fifth of the time after the step
	 * (a ringing response passes through the band, and a trace may end
	 * just then) */
	if (!out_seen) {
		m->settled = 1;
		m->settle_s = 0;
	} else {
		double t_end = tr->t[tr->n - 1];

		m->settled = last_out + 1 < tr->n &&
			     t_end - tr->t[last_out + 1] >= SETTLED_SHARE * t_end;
		m->settle_s = m->settled ? tr->t[last_out + 1] : NAN;
	}
	m->rise_s = t90 - t10;
	return isnan(t90) ? -1 : 0;
}
