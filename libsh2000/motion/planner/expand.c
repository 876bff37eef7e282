// SPDX-License-Identifier: MIT
/*
 * The expansion of a NURBS into planner blocks: each knot span is cut into
 * PL_NURBS_SUBDIV blocks whose speed limit comes from the curvature there,
 * so the look-ahead sees the curve's slow parts before it reaches them.
 * Expansion goes as far as the window has room and resumes as the
 * controller frees blocks.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

int pl_nurbs_expand(struct sh2000_path *p)
{
	struct pl_nurbs *nb = p->pending;

	while (nb && p->count < p->cap) {
		struct pl_block b;
		double u0, u1, du, ks, vl = INFINITY, tt[SH2000_AXES];
		unsigned int i, ax;

		if (nb->span >= nb->c.npoints) {
			nb->expanded = 1;
			p->pending = NULL;
			if (nb->refs == 0) {
				nb->refs = 1;
				pl_nurbs_put(p, nb);
			}
			return 1;
		}
		if (nb->c.knots[nb->span] >= nb->c.knots[nb->span + 1]) {
			nb->span++;
			continue;
		}
		du = (nb->c.knots[nb->span + 1] - nb->c.knots[nb->span]) / PL_NURBS_SUBDIV;
		u0 = nb->c.knots[nb->span] + du * nb->sub;
		u1 = nb->sub + 1 == PL_NURBS_SUBDIV ? nb->c.knots[nb->span + 1]
						    : u0 + du;
		if (++nb->sub == PL_NURBS_SUBDIV) {
			nb->sub = 0;
			nb->span++;
		}
		memset(&b, 0, sizeof(b));
		b.type = BLK_NURBS;
		b.feed = p->pending_feed;
		b.g.nurbs.nb = nb;
		b.g.nurbs.u0 = u0;
		b.g.nurbs.u1 = u1;
		b.L = pl_nurbs_length(nb, u0, u1);
		/* the speed limit over the block: five samples */
		for (i = 0; i <= 4; i++) {
			/* the end from the left: at a C0 knot the next
			 * span's tangent is another one (a corner) */
			double u = i < 4 ? u0 + (u1 - u0) * i / 4.0
					 : u1 - (u1 - u0) * 1e-9;

			pl_nurbs_frame(nb, u, tt, &ks);
			vl = fmin(vl, pl_curve_vlim(p, tt, ks));
			if (i == 0)
				memcpy(b.t0, tt, sizeof(tt));
			if (i == 4)
				memcpy(b.t1, tt, sizeof(tt));
		}
		b.vlim = vl;
		pl_nurbs_eval(nb, u0, b.p0, NULL, NULL);
		pl_nurbs_eval(nb, u1, b.p1, NULL, NULL);
		for (ax = 0; ax < SH2000_AXES; ax++)
			if (!isfinite(b.p1[ax]))
				b.p1[ax] = b.p0[ax];
		nb->refs++;
		pl_push_block(p, &b);
	}
	if (nb && nb->span >= nb->c.npoints) {
		nb->expanded = 1;
		p->pending = NULL;
		nb->refs++;
		pl_nurbs_put(p, nb);
		return 1;
	}
	return nb ? 0 : 1;
}
