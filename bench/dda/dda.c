// SPDX-License-Identifier: MIT
/*
 * The DDA paper [R3]'s digital differential analyser, in software: the
 * reference the planner's accuracy is compared against, not a path to the card.
 *
 * Each axis has an integrand register and a remainder register of `bits`
 * bits. Every cycle adds the integrand to the remainder; an overflow is one
 * pulse. A line loads |delta| as integrand, so after 2^bits cycles each
 * axis has pulsed |delta| times; a position counter per axis stops it at
 * exactly |delta|. Half-loading presets the remainders to half capacity,
 * which rounds instead of truncating (the first pulse comes at half the
 * interval). Left-shift normalisation shifts all integrands together until
 * the largest has its top bit set: the ratios stay, and the fastest axis
 * pulses at least every second cycle.
 *
 * Arcs (2 axes) swap the integrands (x integrates |y|, y integrates |x|)
 * and update them as the point moves. The arc is run one quadrant at a time
 * so that the directions are constant and the counters exact.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dda.h"

struct dda_run {
	const struct sh2000_dda_config *cfg;
	sh2000_dda_step_fn fn;
	void *ctx;
	struct sh2000_dda_result *res;
	uint64_t gap;
	int32_t pos[3];
};

static void account(struct dda_run *r, unsigned int mask)
{
	unsigned int i;

	r->res->iterations++;
	if (!mask) {
		r->gap++;
		if (r->gap > r->res->max_gap)
			r->res->max_gap = r->gap;
		return;
	}
	r->gap = 0;
	for (i = 0; i < 3; i++)
		if (mask & (1u << i))
			r->res->pulses[i]++;
	if (r->fn)
		r->fn(r->ctx, r->pos, mask);
}

static unsigned int norm_shift(uint64_t cap, uint64_t max)
{
	unsigned int k = 0;

	if (!max)
		return 0;
	while ((max << (k + 1)) < cap)
		k++;
	return k;
}

int sh2000_dda_line(const struct sh2000_dda_config *cfg,
		    const int32_t start[3], const int32_t end[3],
		    sh2000_dda_step_fn fn, void *ctx,
		    struct sh2000_dda_result *res)
{
	struct dda_run run = { cfg, fn, ctx, res, 0, { 0 } };
	uint64_t cap, J[3], R[3], cnt[3], max = 0;
	int sgn[3];
	unsigned int i, k = 0;

	if (!cfg || !start || !end || !res || cfg->bits < 2 || cfg->bits > 31)
		return -EINVAL;
	memset(res, 0, sizeof(*res));
	cap = 1ull << cfg->bits;
	for (i = 0; i < 3; i++) {
		int64_t d = (int64_t)end[i] - start[i];

		cnt[i] = (uint64_t)(d < 0 ? -d : d);
		sgn[i] = d < 0 ? -1 : 1;
		if (cnt[i] >= cap)
			return -ERANGE;
		if (cnt[i] > max)
			max = cnt[i];
		run.pos[i] = start[i];
	}
	if (cfg->normalize)
		k = norm_shift(cap, max);
	for (i = 0; i < 3; i++) {
		J[i] = cnt[i] << k;
		R[i] = cfg->half_load ? cap / 2 : 0;
	}
	while (cnt[0] || cnt[1] || cnt[2]) {
		unsigned int mask = 0;

		for (i = 0; i < 3; i++) {
			if (!cnt[i])
				continue;
			R[i] += J[i];
			if (R[i] >= cap) {
				R[i] -= cap;
				run.pos[i] += sgn[i];
				cnt[i]--;
				mask |= 1u << i;
			}
		}
		account(&run, mask);
	}
	memcpy(res->end, run.pos, sizeof(res->end));
	return 0;
}

/* One quadrant piece from the current point to (bx, by). */
static int arc_piece(struct dda_run *run, int64_t cx, int64_t cy,
		     int64_t bx, int64_t by, int ccw, unsigned int k,
		     uint64_t cap, uint64_t *R)
{
	int64_t x = run->pos[0] - cx, y = run->pos[1] - cy;
	uint64_t cntx = (uint64_t)llabs(bx - x), cnty = (uint64_t)llabs(by - y);
	int sx = bx >= x ? 1 : -1, sy = by >= y ? 1 : -1;
	uint64_t guard = 4 * cap + 16;

	(void)ccw;
	while (cntx || cnty) {
		unsigned int mask = 0;
		/* the DDA paper's swapped integrands, read before either moves */
		uint64_t jx = (uint64_t)(llabs(y) ? llabs(y) : 1) << k;
		uint64_t jy = (uint64_t)(llabs(x) ? llabs(x) : 1) << k;

		if (!guard--)
			return -ERANGE;
		if (cntx) {
			R[0] += jx;
			if (R[0] >= cap) {
				R[0] -= cap;
				x += sx;
				run->pos[0] += sx;
				cntx--;
				mask |= 1;
			}
		}
		if (cnty) {
			R[1] += jy;
			if (R[1] >= cap) {
				R[1] -= cap;
				y += sy;
				run->pos[1] += sy;
				cnty--;
				mask |= 2;
			}
		}
		account(run, mask);
	}
	return 0;
}

int sh2000_dda_arc(const struct sh2000_dda_config *cfg,
		   const int32_t centre[2], const int32_t start[2],
		   const int32_t end[2], int ccw,
		   sh2000_dda_step_fn fn, void *ctx,
		   struct sh2000_dda_result *res)
{
	struct dda_run run = { cfg, fn, ctx, res, 0, { 0 } };
	double xs, ys, xe, ye, rs, re, ths, the, sweep, q = M_PI / 2.0;
	uint64_t cap, R[2];
	int64_t r;
	unsigned int k = 0;
	int n, i, ret;

	if (!cfg || !centre || !start || !end || !res || cfg->bits < 2 ||
	    cfg->bits > 31)
		return -EINVAL;
	memset(res, 0, sizeof(*res));
	cap = 1ull << cfg->bits;
	xs = (double)start[0] - centre[0];
	ys = (double)start[1] - centre[1];
	xe = (double)end[0] - centre[0];
	ye = (double)end[1] - centre[1];
	rs = hypot(xs, ys);
	re = hypot(xe, ye);
	r = llround(rs);
	if (r < 1 || llround(re) != r)
		return -EINVAL;
	if ((uint64_t)(r + 1) >= cap)
		return -ERANGE;
	if (cfg->normalize)
		k = norm_shift(cap, (uint64_t)r + 1);
	R[0] = R[1] = cfg->half_load ? cap / 2 : 0;
	run.pos[0] = start[0];
	run.pos[1] = start[1];
	ths = atan2(ys, xs);
	the = atan2(ye, xe);
	sweep = ccw ? the - ths : ths - the;
	while (sweep <= 1e-12)
		sweep += 2.0 * M_PI;
	/* the axis crossings strictly inside the sweep, then the end */
	n = (int)ceil(4.0 * (sweep + 1e-12) / (2.0 * M_PI)) + 1;
	for (i = 1; i <= n; i++) {
		double b = ccw ? (floor(ths / q + 1e-9) + i) * q
			       : (ceil(ths / q - 1e-9) - i) * q;
		double done = ccw ? b - ths : ths - b;
		int64_t bx, by;

		if (done >= sweep - 1e-9)
			break;
		bx = llround(r * cos(b));
		by = llround(r * sin(b));
		ret = arc_piece(&run, centre[0], centre[1], bx, by, ccw, k,
				cap, R);
		if (ret)
			return ret;
	}
	ret = arc_piece(&run, centre[0], centre[1], (int64_t)end[0] - centre[0],
			(int64_t)end[1] - centre[1], ccw, k, cap, R);
	if (ret)
		return ret;
	res->end[0] = run.pos[0];
	res->end[1] = run.pos[1];
	res->end[2] = 0;
	return 0;
}
