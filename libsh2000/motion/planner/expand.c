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

/* A cusp between two samples: the tangent there turns by more than 90
 * degrees, which a smooth curve sampled this densely only does where its
 * derivative passes through zero (the carriage must stop and reverse).
 * Bisection on the sign of C'(u) . t0 finds where it turns; both sides
 * are then blocks of their own, so their junction stops the motion. */
static double find_cusp(const struct pl_nurbs *nb, double lo, double hi,
			const double t0[SH2000_AXES])
{
	double c[SH2000_AXES], d1[SH2000_AXES];

	for (unsigned int it = 0; it < 60 && hi - lo > 1e-15 * (1.0 + fabs(hi)); it++) {
		double m = 0.5 * (lo + hi);

		pl_nurbs_eval(nb, m, c, d1, NULL);
		if (pl_dot(d1, t0) > 0.0)
			lo = m;
		else
			hi = m;
	}
	return 0.5 * (lo + hi);
}

/* Where the block's five samples lie, the ends taken from inside the
 * block: at a C0 knot or a cusp the other side's tangent is another one
 * (a corner). */
static double sample_u(double u0, double u1, unsigned int i)
{
	return i == 0 ? u0 + (u1 - u0) * 1e-9 :
	       i < 4 ? u0 + (u1 - u0) * i / 4.0 : u1 - (u1 - u0) * 1e-9;
}

static void sample_block(const struct pl_nurbs *nb, double u0, double u1,
			 unsigned int i, double t[SH2000_AXES], double *speed,
			 double *kappa)
{
	*speed = pl_nurbs_frame(nb, sample_u(u0, u1, i), t, kappa);
}

/* A candidate block [u0, u1] of a curve, looked at through five samples. */
struct probe {
	double u0, u1;
	double t[5][SH2000_AXES], speed[5], kappa[5];
	double L, vlim, vhigh;	/* length; lowest and highest sample limit */
	int cusp;		/* u1 was brought back to a cusp */
};

/* A cusp between two samples shortens the block to it. */
static void find_cusp_in(const struct pl_nurbs *nb, struct probe *pr)
{
	double u0 = pr->u0, u1 = pr->u1;
	unsigned int i, last = 0;

	for (i = 0; i <= 4; i++) {
		sample_block(nb, u0, u1, i, pr->t[i], &pr->speed[i], &pr->kappa[i]);
		if (i > 0 && pl_dot(pr->t[last], pr->t[i]) < 0.0) {
			double uc = find_cusp(nb, sample_u(u0, u1, last),
					      sample_u(u0, u1, i), pr->t[last]);

			/* one so close to the start is the start's:
			 * splitting there would not move the carriage */
			if (uc - u0 > 1e-6 * (u1 - u0)) {
				pr->u1 = uc;
				pr->cusp = 1;
				return;
			}
		}
		if (pl_dot(pr->t[i], pr->t[i]) > 0.5)
			last = i;	/* a zero tangent has no say */
	}
}

static void probe_block(const struct sh2000_path *p,
			const struct pl_nurbs *nb, struct probe *pr)
{
	double still, lo, hi;
	unsigned int i;

	pr->cusp = 0;
	find_cusp_in(nb, pr);
	if (pr->cusp)	/* the block ends at the cusp: sampled anew */
		for (i = 0; i <= 4; i++)
			sample_block(nb, pr->u0, pr->u1, i, pr->t[i],
				     &pr->speed[i], &pr->kappa[i]);
	lo = hi = pr->speed[0];
	for (i = 1; i <= 4; i++) {
		lo = fmin(lo, pr->speed[i]);
		hi = fmax(hi, pr->speed[i]);
	}
	pr->L = hi <= 4.0 * lo ? pl_nurbs_length_even(nb, pr->u0, pr->u1)
			       : pl_nurbs_length(nb, pr->u0, pr->u1);
	/* the speed limit over the block from its samples, but not from one
	 * where the curve nearly stands still: that is a cusp, whose
	 * curvature grows without bound while the junction stops the
	 * carriage there anyway */
	still = 1e-3 * pr->L / (pr->u1 - pr->u0);
	pr->vlim = INFINITY;
	pr->vhigh = 0.0;
	for (i = 0; i <= 4; i++)
		if (pr->speed[i] >= still) {
			double v = pl_curve_vlim(p, pr->t[i], pr->kappa[i]);

			pr->vlim = fmin(pr->vlim, v);
			pr->vhigh = fmax(pr->vhigh, v);
		}
}

/* A block whose speed limit varies more than this within it is halved:
 * its lowest sample holds the whole block, so the closer the blocks
 * follow the curve's limit, the less the carriage waits before and after
 * a tight turn. bench_feed, compensated, the card model's limits, cycle
 * time over L/F: the free-form NURBS at 150 mm/s 1.657 at 4, 1.644 at
 * 1.5, 1.603 at 1.2, 1.604 at 1.1; the butterfly at 300 mm/s 1.569,
 * 1.566 at 1.2, 1.552 at 1.1. The planner's throughput on free-form
 * NURBS falls with the blocks (bench_planner throughput freeform on a
 * loaded machine: 266,000 points/s at 4, 194,000 at 1.2, 112,000 at 1.1). */
#define NURBS_SPLIT_RATIO 1.2

/* Halvings of a sixteenth of a span at most (4096 pieces). */
#define PL_NURBS_SPLIT_MIN (1.0 / 4096.0)

int pl_nurbs_expand(struct sh2000_path *p)
{
	struct pl_nurbs *nb = p->pending;

	while (nb && p->count < p->cap) {
		struct pl_block b;
		struct probe pr;
		double du;
		unsigned int ax;
		int split = 0;

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
		pr.u0 = nb->c.knots[nb->span] + du * nb->sub;
		pr.u1 = nb->sub + 1 == PL_NURBS_SUBDIV ? nb->c.knots[nb->span + 1]
						       : pr.u0 + du;
		if (nb->cut > pr.u0 && nb->cut < pr.u1)
			pr.u0 = nb->cut;	/* the rest after a cut */
		probe_block(p, nb, &pr);
		/* where the limit changes within the block (a tight turn,
		 * where a heavy weight crowds the parameter, or the approach
		 * to a sharp turn), halve it: the low limit would hold the
		 * whole block back */
		while (pr.vhigh > NURBS_SPLIT_RATIO * pr.vlim &&
		       pr.u1 - pr.u0 > du * PL_NURBS_SPLIT_MIN) {
			pr.u1 = 0.5 * (pr.u0 + pr.u1);
			probe_block(p, nb, &pr);
			split = 1;
		}
		nb->cut = pr.cusp || split ? pr.u1 : NAN;
		if (isnan(nb->cut) && ++nb->sub == PL_NURBS_SUBDIV) {
			nb->sub = 0;
			nb->span++;
		}
		memset(&b, 0, sizeof(b));
		b.type = BLK_NURBS;
		b.feed = p->pending_feed;
		b.g.nurbs.nb = nb;
		b.g.nurbs.u0 = pr.u0;
		b.g.nurbs.u1 = pr.u1;
		b.L = pr.L;
		b.vlim = pr.vlim;
		memcpy(b.t0, pr.t[0], sizeof(b.t0));
		memcpy(b.t1, pr.t[4], sizeof(b.t1));
		pl_nurbs_eval(nb, pr.u0, b.p0, NULL, NULL);
		pl_nurbs_eval(nb, pr.u1, b.p1, NULL, NULL);
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
