// SPDX-License-Identifier: MIT
/*
 * Pieces of lines and arcs: a blend (blend.c) replaces the ends of the two
 * blocks at a corner, so it needs the blocks cut short and the pieces it
 * cut away (to measure how far the blend strays from them). An arc's
 * piece is the same arc over a part of its sweep; the arc's frame (length
 * and end tangents) is one formula for whole arcs and pieces.
 */
#include <string.h>
#include <math.h>

#include "planner.h"

void pl_arc_frame(struct pl_block *b)
{
	const struct sh2000_arc *g = &b->g.arc;
	double lin2 = 0.0, planar, f, sgn = g->sweep > 0.0 ? 1.0 : -1.0;
	double th1 = g->th0 + g->sweep;
	unsigned int i = g->first, j = g->second, a;

	for (a = 0; a < SH2000_AXES; a++)
		if (a != i && a != j)
			lin2 += (b->p1[a] - b->p0[a]) * (b->p1[a] - b->p0[a]);
	planar = fabs(g->sweep) * 0.5 * (g->r0 + g->r1);
	b->L = sqrt(planar * planar + lin2);
	f = planar / b->L;
	for (a = 0; a < SH2000_AXES; a++) {
		double l = (a != i && a != j) ? (b->p1[a] - b->p0[a]) / b->L : 0.0;

		b->t0[a] = b->t1[a] = l;
	}
	b->t0[i] = -sgn * f * sin(g->th0);
	b->t0[j] = sgn * f * cos(g->th0);
	b->t1[i] = -sgn * f * sin(th1);
	b->t1[j] = sgn * f * cos(th1);
}

void pl_block_cut(const struct pl_block *b, double s0, double s1,
		  struct pl_block *out)
{
	struct pl_block k = *b;
	unsigned int a;

	if (b->type == BLK_LINE) {
		for (a = 0; a < SH2000_AXES; a++) {
			k.p0[a] = b->p0[a] + s0 * b->g.line.d[a];
			k.p1[a] = b->p0[a] + s1 * b->g.line.d[a];
		}
		/* the far ends exactly where they were */
		if (s0 <= 0.0)
			memcpy(k.p0, b->p0, sizeof(k.p0));
		if (s1 >= b->L)
			memcpy(k.p1, b->p1, sizeof(k.p1));
		k.L = s1 - s0;
	} else {	/* BLK_ARC: the arc is uniform in its fraction */
		const struct sh2000_arc *g = &b->g.arc;
		double f0 = s0 / b->L, f1 = s1 / b->L;

		if (s0 > 0.0)
			sh2000_arc_point(g, b->p0, b->p1, f0, k.p0);
		if (s1 < b->L)
			sh2000_arc_point(g, b->p0, b->p1, f1, k.p1);
		k.g.arc.th0 = g->th0 + f0 * g->sweep;
		k.g.arc.sweep = (f1 - f0) * g->sweep;
		k.g.arc.r0 = g->r0 + f0 * (g->r1 - g->r0);
		k.g.arc.r1 = g->r0 + f1 * (g->r1 - g->r0);
		pl_arc_frame(&k);
	}
	*out = k;
}
