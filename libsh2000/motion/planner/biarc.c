// SPDX-License-Identifier: MIT
/*
 * Blend curves made of circular arcs in any plane of the four axes: the
 * arc from a point along a tangent to another point, and the biarc, two
 * such arcs meeting tangentially, from a point and tangent to another
 * point and tangent. Every point and tangent is given in axis space, so
 * a blend between a line and a helix, or two arcs in different planes,
 * is built the same way as one between two lines.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

int pl_arc_to(const struct sh2000_path *p, const double a[SH2000_AXES],
	      const double ta[SH2000_AXES], const double b[SH2000_AXES],
	      double feed, double smax, struct pl_block *k)
{
	double c[SH2000_AXES], n[SH2000_AXES], tt[SH2000_AXES];
	double L = 0.0, ca, sa = 0.0, al, R;
	unsigned int i;

	for (i = 0; i < SH2000_AXES; i++) {
		c[i] = b[i] - a[i];
		L += c[i] * c[i];
	}
	L = sqrt(L);
	if (!(L > 1e-12))
		return -1;
	ca = pl_dot(ta, c) / L;		/* cos of half the turn */
	if (ca <= 0.0)
		return -1;		/* a turn of 180 degrees or more */
	for (i = 0; i < SH2000_AXES; i++) {
		n[i] = c[i] / L - ca * ta[i];
		sa += n[i] * n[i];
	}
	sa = sqrt(sa);
	memset(k, 0, sizeof(*k));
	k->feed = feed;
	memcpy(k->p0, a, sizeof(k->p0));
	memcpy(k->p1, b, sizeof(k->p1));
	memcpy(k->t0, ta, sizeof(k->t0));
	if (sa < 1e-9) {	/* straight on: a line */
		k->type = BLK_LINE;
		k->L = L;
		memcpy(k->g.line.d, ta, sizeof(k->g.line.d));
		memcpy(k->t1, ta, sizeof(k->t1));
		k->vlim = pl_curve_vlim(p, ta, 0.0);
		return 0;
	}
	al = atan2(sa, ca);
	R = L / (2.0 * sa);
	k->type = BLK_BLEND;
	for (i = 0; i < SH2000_AXES; i++) {
		n[i] /= sa;	/* towards the centre */
		k->g.blend.c[i] = a[i] + R * n[i];
		k->g.blend.u[i] = -n[i];
		k->g.blend.w[i] = ta[i];
		k->t1[i] = cos(2.0 * al) * ta[i] + sin(2.0 * al) * n[i];
		/* the most of axis i's share the turning tangent reaches */
		tt[i] = sqrt(ta[i] * ta[i] + n[i] * n[i]);
	}
	k->g.blend.R = R;
	k->g.blend.phi = 2.0 * al;
	k->L = R * 2.0 * al;
	pl_curve_block_vlim(p, k, tt, 1.0 / R, smax);
	return 0;
}

/*
 * The biarc of equal tangent lengths d: from a along ta to q1 = a + d ta,
 * from b back along tb to q2 = b - d tb, and |q2 - q1| = 2d, so the two
 * arcs meet in the middle m of q1 q2 with the tangent along q2 - q1:
 * d^2 (tt - 4) - 2 d (v.t) + v.v = 0 with v = b - a, t = ta + tb.
 */
unsigned int pl_biarc(const struct sh2000_path *p,
		      const double a[SH2000_AXES], const double ta[SH2000_AXES],
		      const double b[SH2000_AXES], const double tb[SH2000_AXES],
		      double feed, double smax, struct pl_block k[2])
{
	double v[SH2000_AXES], t[SH2000_AXES], m[SH2000_AXES], tm[SH2000_AXES];
	double vt, vv, c = pl_dot(ta, tb), d, nm = 0.0;
	unsigned int i;

	for (i = 0; i < SH2000_AXES; i++) {
		v[i] = b[i] - a[i];
		t[i] = ta[i] + tb[i];
	}
	vt = pl_dot(v, t);
	vv = pl_dot(v, v);
	if (1.0 - c < 1e-12)
		d = vt > 0.0 ? vv / (2.0 * vt) : -1.0;
	else
		d = (-vt + sqrt(vt * vt + 2.0 * (1.0 - c) * vv)) /
		    (2.0 * (1.0 - c));
	if (!(d > 0.0) || !isfinite(d))
		return 0;
	for (i = 0; i < SH2000_AXES; i++) {
		double q1 = a[i] + d * ta[i], q2 = b[i] - d * tb[i];

		m[i] = 0.5 * (q1 + q2);
		tm[i] = q2 - q1;
		nm += tm[i] * tm[i];
	}
	nm = sqrt(nm);
	if (!(nm > 0.0))
		return 0;
	for (i = 0; i < SH2000_AXES; i++)
		tm[i] /= nm;
	if (pl_arc_to(p, a, ta, m, feed, smax, &k[0]) ||
	    pl_arc_to(p, m, tm, b, feed, smax, &k[1]))
		return 0;
	/* the tangents where they meet and at the end exactly as the
	 * neighbours have them: the junctions are tangent */
	memcpy(k[0].t1, tm, sizeof(tm));
	memcpy(k[1].t1, tb, sizeof(k[1].t1));
	if (k[1].type == BLK_LINE)
		memcpy(k[1].g.line.d, tm, sizeof(tm));
	return 2;
}
