// SPDX-License-Identifier: MIT
/*
 * Speed limits from the geometry: along a curve (axis speeds, centripetal
 * acceleration, chord tolerance, jerk) and through the corner between two
 * blocks (the corner tolerance, the axes' acceleration over one period
 * and what the card's B-spline does to a corner); and the acceleration
 * along each block (a line's axes each up to their own amax, a curve's
 * tangential share).
 */
#include <math.h>
#include <string.h>

#include "planner.h"

/* The speed limit at a point with the centripetal share s. */
static double vlim_share(const struct sh2000_path *p,
			 const double t[SH2000_AXES], double kappa, double s)
{
	const struct sh2000_path_config *c = &p->cfg;
	double v = INFINITY;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (fabs(t[a]) > 1e-12)
			v = fmin(v, c->margin * c->vmax[a] / fabs(t[a]));
	if (kappa > 1e-12) {
		double share = s * c->margin;

		v = fmin(v, sqrt(share * p->amin / kappa));
		v = fmin(v, sqrt(8.0 * c->chord_tol / kappa) / c->period_s);
		if (!isinf(p->lim.J))
			v = fmin(v, cbrt(share * p->lim.J / (kappa * kappa)));
	}
	return v;
}

double pl_curve_vlim(const struct sh2000_path *p, const double t[SH2000_AXES],
		     double kappa)
{
	return vlim_share(p, t, kappa, p->cfg.centripetal_share);
}

void pl_curve_block_vlim(const struct sh2000_path *p, struct pl_block *k,
			 const double t[SH2000_AXES], double kappa,
			 double smax)
{
	double s0 = p->cfg.centripetal_share, s1 = pl_max(s0, smax);
	double f = k->feed > 0.0 ? k->feed : INFINITY;
	double lo = s0, hi = s1;
	unsigned int i;

	k->share = s0;
	k->vlim = vlim_share(p, t, kappa, s0);
	if (k->vlim >= f || s1 <= s0)
		return;
	if (vlim_share(p, t, kappa, s1) <= f) {
		lo = s1;
	} else {	/* the least share that reaches the feed */
		for (i = 0; i < 30; i++) {
			double m = 0.5 * (lo + hi);

			if (vlim_share(p, t, kappa, m) < f)
				lo = m;
			else
				hi = m;
		}
		lo = hi;
	}
	k->share = lo;
	k->vlim = vlim_share(p, t, kappa, lo);
}

/* The largest |x cos(th) + y sin(th)| over th in [0, phi]. */
static double sweep_max(double x, double y, double phi)
{
	double m = fmax(fabs(x), fabs(x * cos(phi) + y * sin(phi)));
	/* the extremes, amplitude hypot(x, y), lie at atan2(y, x) + k pi */
	double th = fmod(atan2(y, x), M_PI);

	if (th < 0.0)
		th += M_PI;
	return th <= phi ? hypot(x, y) : m;
}

/* Along a blend arc, axis by axis: axis i sees at most A T_i of the
 * tangential acceleration A and an N_i of the centripetal an, T_i and N_i
 * the largest share of the tangent and of the normal it takes over the
 * arc's sweep (a short arc keeps close to the direction of its tangent,
 * as a line does). */
static void blend_box_coef(const struct pl_block *b, double T[SH2000_AXES],
			   double N[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double u = b->g.blend.u[a], w = b->g.blend.w[a];

		/* t = w cos - u sin, n = -(u cos + w sin) */
		T[a] = sweep_max(w, -u, b->g.blend.phi);
		N[a] = sweep_max(u, w, b->g.blend.phi);
	}
}

/* The tangential acceleration along a blend with the centripetal share s:
 * at right angles to the centripetal part (their sum within the smallest
 * amax whatever the direction), or where more, the most that keeps every
 * axis within its own amax (as a line's), from blend_box_coef(); before
 * the ringing allowance. */
static double blend_accel_share(const struct sh2000_path *p,
				const struct pl_accel_fn *f, double s)
{
	const struct sh2000_path_config *c = &p->cfg;
	double an = s * c->margin * p->amin, A = INFINITY;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (f->T[a] > 1e-12)
			A = fmin(A, (c->margin * c->amax[a] - an * f->N[a]) /
				    f->T[a]);
	return fmax(sqrt(1.0 - s * s) * c->margin * p->amin,
		    fmax(A, 0.0)) * p->a_scale;
}

/* The centripetal share the speed v gives a blend: v^2 / R of the
 * smallest amax, within [s0, s1]. */
static double share_at(const struct pl_accel_fn *f, double v)
{
	return pl_max(f->s0, pl_min(f->s1, v * v * f->kM));
}

/* Blend arcs of turns under 45 degrees take the share their speed gives
 * them; wider turns keep their block's (pl_block_accel()). */
int pl_accel_dyn(const struct pl_block *b)
{
	return b->type == BLK_BLEND && b->g.blend.phi < M_PI / 4.0;
}

void pl_accel_fn_init(const struct sh2000_path *p, const struct pl_block *b,
		      struct pl_accel_fn *f)
{
	const struct sh2000_path_config *c = &p->cfg;

	f->A = f->Amax = b->A;
	f->dyn = pl_accel_dyn(b);
	if (!f->dyn)
		return;
	f->s0 = c->centripetal_share;
	f->s1 = pl_max(b->share, f->s0);
	f->kM = 1.0 / (b->g.blend.R * c->margin * p->amin);
	blend_box_coef(b, f->T, f->N);
	f->Amax = pl_accel_at(p, f, 0.0);
}

double pl_accel_at(const struct sh2000_path *p, const struct pl_accel_fn *f,
		   double v)
{
	if (!f->dyn)
		return f->A;
	return pl_max(f->A, pl_min(pl_accel_room(p, blend_accel_share(
			p, f, share_at(f, v))), p->a_top));
}

double pl_accel_curv(const struct sh2000_path *p, double v, double kappa)
{
	const struct sh2000_path_config *c = &p->cfg;
	double M = c->margin * p->amin;
	double s = pl_max(c->centripetal_share, v * v * kappa / M);

	if (s >= 1.0)
		return 0.0;
	return pl_min(pl_accel_room(p, sqrt(1.0 - s * s) * M * p->a_scale),
		      p->a_top);
}

double pl_block_accel(const struct sh2000_path *p, const struct pl_block *b)
{
	const struct sh2000_path_config *c = &p->cfg;
	double A = INFINITY;
	unsigned int a;

	if (b->type != BLK_LINE) {
		double s = b->share > c->centripetal_share ? b->share :
			   c->centripetal_share;
		/* tangential and centripetal at right angles (path.c): their
		 * sum within the smallest amax whatever the direction */
		double At = sqrt(1.0 - s * s) * c->margin * p->amin *
			    p->a_scale;

		if (pl_accel_dyn(b)) {
			/* the centripetal acceleration the speed the motion
			 * can reach in it gives it, if that is less; not on
			 * wide turns, where an axis takes the tangential
			 * braking and then the centripetal, both along it
			 * (blend.c, BLEND_SHARE_TURN) */
			struct pl_accel_fn f = { .A = 0.0, .dyn = 1 };

			f.s0 = c->centripetal_share;
			f.s1 = s;
			f.kM = 1.0 / (b->g.blend.R * c->margin * p->amin);
			blend_box_coef(b, f.T, f.N);
			At = blend_accel_share(p, &f, share_at(&f,
							       pl_peak(p, b)));
		} else if (b->type == BLK_BLEND) {
			struct pl_accel_fn f;

			blend_box_coef(b, f.T, f.N);
			At = blend_accel_share(p, &f, s);
		}
		return fmin(pl_accel_room(p, At), p->a_top);
	}
	/* along a line axis i accelerates at A |d_i|: each axis to its own
	 * amax, as LinuxCNC's planner does; the margin as everywhere */
	for (a = 0; a < SH2000_AXES; a++)
		if (fabs(b->g.line.d[a]) > 1e-12)
			A = fmin(A, c->margin * c->amax[a] /
				    fabs(b->g.line.d[a]));
	/* from rest to rest with one jerk a period the card's spline along
	 * a line is the plan itself: no allowance for the path's turns */
	if (b->rest_line)
		return fmin(A * p->a_scale, p->a_top);
	return fmin(pl_accel_room(p, A * p->a_scale), p->a_top);
}

double pl_corner_spline_vlim(const struct sh2000_path *p, double sh,
			     double tol, double k)
{
	return k * tol / (p->cfg.period_s * sh);
}

double pl_junction(const struct sh2000_path *p, const double t1[SH2000_AXES],
		   const double t0[SH2000_AXES])
{
	const struct sh2000_path_config *c = &p->cfg;
	double dot = 0.0, v = INFINITY, ch, sh, T = c->period_s;
	double k = c->output == SH2000_OUTPUT_COMPENSATED ? sqrt(3.0) : 1.0;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		dot += t1[a] * t0[a];
	if (dot > 1.0 - 1e-12)
		return INFINITY;
	/* the corner tolerance: a circle through the corner that deviates
	 * by corner_tol, at the path acceleration */
	ch = sqrt(fmax(0.0, 0.5 * (1.0 + dot)));	/* cos(turn/2) */
	sh = sqrt(fmax(0.0, 0.5 * (1.0 - dot)));	/* sin(turn/2) */
	if (ch < 1e-9 || (k == 1.0 && c->corner_tol < PL_RAW_TOL_REST_MM))
		return 0.0;
	v = sqrt(p->lim.A * c->corner_tol * ch / (1.0 - ch));
	/* the card's spline rounds the corner: half the tolerance for it,
	 * half for the speed changing around it */
	v = fmin(v, pl_corner_spline_vlim(p, sh, c->corner_tol,
					  PL_JUNCTION_SPLINE));
	for (a = 0; a < SH2000_AXES; a++) {
		double dt = fabs(t0[a] - t1[a]);
		double room = c->margin * c->amax[a] - p->lim.A;

		if (dt < 1e-12)
			continue;
		/* the jump in axis speed is an acceleration over one
		 * period, sqrt 3 times larger after compensation */
		v = fmin(v, fmax(room, 0.0) * T / (k * dt));
		/* and the compensation overshoots a speed step by 0.37 */
		if (k > 1.0)
			v = fmin(v, c->margin * c->vmax[a] /
				    (fmax(fabs(t0[a]), fabs(t1[a])) + 0.37 * dt));
	}
	return v * T <= PL_CREEP_MM ? 0.0 : v;	/* a stop, landed */
}

/* The curvature vector (d^2 x / ds^2) of block b at its start (end 0) or
 * its end: 0 on a line, n / R on a blend, by a second difference of its
 * exact points on an arc; 0 with *known 0 for a NURBS (its own expansion
 * bounds the steps inside it). */
static void block_curv(const struct pl_block *b, int end,
		       double k[SH2000_AXES], int *known)
{
	unsigned int a;

	memset(k, 0, SH2000_AXES * sizeof(k[0]));
	*known = b->type != BLK_NURBS;
	if (b->type == BLK_BLEND) {
		double th = end ? b->g.blend.phi : 0.0;

		for (a = 0; a < SH2000_AXES; a++)
			k[a] = -(b->g.blend.u[a] * cos(th) +
				 b->g.blend.w[a] * sin(th)) / b->g.blend.R;
	} else if (b->type == BLK_ARC) {
		double h = pl_min(b->L / 8.0, 0.01), x[3][SH2000_AXES];
		unsigned int i;

		for (i = 0; i < 3; i++)
			pl_block_pos(b, end ? b->L - i * h : i * h, x[i]);
		for (a = 0; a < SH2000_AXES; a++)
			k[a] = (x[0][a] - 2.0 * x[1][a] + x[2][a]) / (h * h);
	}
}

double pl_curv_step(const struct sh2000_path *p, const struct pl_block *b0,
		    const struct pl_block *b1)
{
	const struct sh2000_path_config *c = &p->cfg;
	double k0[SH2000_AXES], k1[SH2000_AXES], v = INFINITY;
	int n0, n1;
	unsigned int a;

	if (c->output != SH2000_OUTPUT_COMPENSATED)
		return INFINITY;
	block_curv(b0, 1, k0, &n0);
	block_curv(b1, 0, k1, &n1);
	if (!n0 || !n1)
		return INFINITY;
	for (a = 0; a < SH2000_AXES; a++) {
		double q = pl_max(fabs(k0[a]), fabs(k1[a])) +
			   PL_CURV_RING * fabs(k1[a] - k0[a]);

		if (q > 1e-12)
			v = pl_min(v, sqrt(c->margin * c->amax[a] / q));
	}
	return v;
}

/* A block's acceleration never passes a_top (pl_block_accel()); 1 % is
 * kept for the controller's roundings. */
double pl_fwd_exit(const struct sh2000_path *p, const struct pl_block *b)
{
	return pl_min(b->vlim, sqrt(b->vin * b->vin +
				    2.02 * p->a_top * b->L));
}

double pl_peak(const struct sh2000_path *p, const struct pl_block *b)
{
	double d = 2.02 * p->a_top * b->L, v = pl_fwd_exit(p, b);

	if (isinf(b->vout))
		return v;
	v = pl_min(v, sqrt(b->vout * b->vout + d));
	/* up from vin and down to vout within L */
	return pl_min(v, sqrt(0.5 * (b->vin * b->vin + b->vout * b->vout +
				     d)));
}

int pl_ring_zone(const struct sh2000_path *p, const struct pl_block *b,
		 double s)
{
	double zone = 2.0 * p->cfg.period_s;

	return b->rest_line && b->ring_start &&
	       s < zone * (b->vin + b->A * zone);
}
