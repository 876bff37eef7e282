// SPDX-License-Identifier: MIT
/*
 * Pieces of lines, arcs and NURBS blocks: a blend (blend.c) replaces the
 * ends of the two blocks at a corner, so it needs the blocks cut short and
 * the pieces it cut away (to measure how far the blend strays from them).
 * An arc's piece is the same arc over a part of its sweep; the arc's frame
 * (length and end tangents) is one formula for whole arcs and pieces. A
 * NURBS block's piece is the curve over a part of the block's parameter
 * range, found by arc length.
 */
#include <string.h>
#include <math.h>

#include "planner.h"

/*
 * The arc is a spiral when the programmed centre is not equidistant from
 * its ends: the radius runs linearly from r0 to r1 with the angle. Its
 * planar speed along the fraction f is |dr e_r + r(f) sweep e_th|; that
 * radial part is negligible on a real arc but is all of it on an arc of
 * enormous radius whose sweep rounds to nothing, so length and tangents
 * count it rather than take the arc for a circle.
 */
static double arc_planar_speed(const struct sh2000_arc *g, double f)
{
	double dr = g->r1 - g->r0, u = (g->r0 + f * dr) * g->sweep;

	return sqrt(u * u + dr * dr);
}

/* The unit tangent where the angle is th and the planar speed's
 * tangential part u = r sweep; lin: the linear axes' travel. */
static void arc_end_tangent(const double lin[SH2000_AXES], double lin2,
			    double dr, double u, double th, unsigned int i,
			    unsigned int j, double t[SH2000_AXES])
{
	double n = sqrt(u * u + dr * dr + lin2);
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		t[a] = lin[a] / n;
	t[i] = (dr * cos(th) - u * sin(th)) / n;
	t[j] = (dr * sin(th) + u * cos(th)) / n;
}

void pl_arc_frame(struct pl_block *b)
{
	const struct sh2000_arc *g = &b->g.arc;
	double lin[SH2000_AXES], lin2 = 0.0, planar;
	double th1 = g->th0 + g->sweep, dr = g->r1 - g->r0;
	unsigned int i = g->first, j = g->second, a;

	for (a = 0; a < SH2000_AXES; a++) {
		lin[a] = (a != i && a != j) ? b->p1[a] - b->p0[a] : 0.0;
		lin2 += lin[a] * lin[a];
	}
	/* Simpson's rule: the speed is smooth and nearly linear in f */
	planar = (arc_planar_speed(g, 0.0) + 4.0 * arc_planar_speed(g, 0.5) +
		  arc_planar_speed(g, 1.0)) / 6.0;
	b->L = sqrt(planar * planar + lin2);
	arc_end_tangent(lin, lin2, dr, g->r0 * g->sweep, g->th0, i, j, b->t0);
	arc_end_tangent(lin, lin2, dr, g->r1 * g->sweep, th1, i, j, b->t1);
}

/* The NURBS block b between arc lengths s0 and s1 into k (a copy of b):
 * the parameters there, the ends' points and tangents, the length. */
static void nurbs_cut(const struct pl_block *b, double s0, double s1,
		      struct pl_block *k)
{
	const struct pl_nurbs *nb = b->g.nurbs.nb;
	double u0 = b->g.nurbs.u0, u1 = b->g.nurbs.u1, len, kappa;

	if (s0 > 0.0) {
		k->g.nurbs.u0 = pl_nurbs_u_at(nb, u0, u1, b->L, s0, &len);
		pl_nurbs_eval(nb, k->g.nurbs.u0, k->p0, NULL, NULL);
		pl_nurbs_frame(nb, k->g.nurbs.u0, k->t0, &kappa);
	}
	if (s1 < b->L) {
		k->g.nurbs.u1 = pl_nurbs_u_at(nb, u0, u1, b->L, s1, &len);
		pl_nurbs_eval(nb, k->g.nurbs.u1, k->p1, NULL, NULL);
		pl_nurbs_frame(nb, k->g.nurbs.u1, k->t1, &kappa);
	}
	if (s0 > 0.0 || s1 < b->L)
		k->L = pl_nurbs_length(nb, k->g.nurbs.u0, k->g.nurbs.u1);
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
	} else if (b->type == BLK_NURBS) {
		nurbs_cut(b, s0, s1, &k);
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
