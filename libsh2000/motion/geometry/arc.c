// SPDX-License-Identifier: MIT
/*
 * Arcs (sh2000/geometry.h): the centre of a radius-form arc and the
 * resolution of a centre-form arc, with LinuxCNC's rules (rs274ngc's
 * arc_data_r and arc_data_ijk), so a program that LinuxCNC accepts is
 * accepted here and draws the same circle.
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/geometry.h"

#define MSG(code, ...) \
	(msg && len ? (void)snprintf(msg, len, __VA_ARGS__) : (void)0, (code))

int sh2000_arc_centre_from_radius(const double s[2], const double e[2],
				  double r, bool ccw, double centre[2],
				  char *msg, size_t len)
{
	double abs_r = fabs(r), mid0, mid1, half, theta, offset;

	if (!isfinite(r) || abs_r < SH2000_ARC_RADIUS_TOL_MM)
		return MSG(-EINVAL, "arc radius %g mm is not a usable radius", r);
	if (abs_r > SH2000_ARC_MAX_MM)
		return MSG(-ERANGE,
			   "arc radius %g mm is beyond %g mm: its points would round to more than a nanometre",
			   r, SH2000_ARC_MAX_MM);
	if (e[0] == s[0] && e[1] == s[1])
		return MSG(-EINVAL,
			   "R-format arc ends where it starts: the centre is undefined (use I/J/K for a full circle)");
	mid0 = (e[0] + s[0]) / 2;
	mid1 = (e[1] + s[1]) / 2;
	half = hypot(mid0 - e[0], mid1 - e[1]);
	if (half - abs_r > SH2000_ARC_RADIUS_TOL_MM)
		return MSG(-EINVAL,
			   "arc radius %.4f mm too small to reach the end point (half chord %.4f mm)",
			   abs_r, half);
	if (half / abs_r > 1 - 1e-12)
		half = abs_r;
	/* G2 with R > 0 or G3 with R < 0 has its centre right of the chord */
	if ((!ccw && r > 0) || (ccw && r < 0))
		theta = atan2(e[1] - s[1], e[0] - s[0]) - M_PI_2;
	else
		theta = atan2(e[1] - s[1], e[0] - s[0]) + M_PI_2;
	offset = abs_r * cos(asin(half / abs_r));
	centre[0] = mid0 + offset * cos(theta);
	centre[1] = mid1 + offset * sin(theta);
	return 0;
}

/* The point of the chord's perpendicular bisector nearest to the centre:
 * a true circle through both ends. */
static void fit_circle(struct sh2000_arc *a, const double s[2],
		       const double e[2], double same_mm)
{
	double len = hypot(e[0] - s[0], e[1] - s[1]);
	double u0, u1, m0, m1, t;

	memcpy(a->fit_centre, a->centre, sizeof(a->fit_centre));
	a->fit_radius = a->r0;
	if (len < fmax(same_mm, 1e-9))
		return;
	u0 = -(e[1] - s[1]) / len;
	u1 = (e[0] - s[0]) / len;
	m0 = (s[0] + e[0]) / 2;
	m1 = (s[1] + e[1]) / 2;
	t = (a->centre[0] - m0) * u0 + (a->centre[1] - m1) * u1;
	a->fit_centre[0] = m0 + t * u0;
	a->fit_centre[1] = m1 + t * u1;
	a->fit_radius = hypot(s[0] - a->fit_centre[0], s[1] - a->fit_centre[1]);
}

/* Signed sweep from th0 to th1 in the arc's sense plus the extra turns;
 * full: the end is the start (a whole circle). */
static double sweep_of(double th0, double th1, bool ccw, unsigned int turns,
		       bool full)
{
	double d = full ? 0 : th1 - th0;

	if (ccw) {
		while (d <= 0)
			d += 2 * M_PI;
		while (d > 2 * M_PI)
			d -= 2 * M_PI;
		return d + 2 * M_PI * (turns - 1);
	}
	while (d >= 0)
		d -= 2 * M_PI;
	while (d < -2 * M_PI)
		d += 2 * M_PI;
	return d - 2 * M_PI * (turns - 1);
}

/* The radii and centre within SH2000_ARC_MAX_MM, and an arc that is not a
 * full circle turning from start to end by more than the rounding of the
 * two angles (each point's coordinates round by DBL_EPSILON times the
 * largest of them, an angle by that over the radius): otherwise the sweep
 * is noise, and a sweep that rounds to zero becomes a whole turn. */
static int check_resolvable(const struct sh2000_arc *a, const double s[2],
			    const double e[2], bool full, char *msg,
			    size_t len)
{
	const char *n = SH2000_AXIS_LETTERS;
	double m = fmax(fmax(fabs(s[0]), fabs(s[1])),
			fmax(fabs(e[0]), fabs(e[1])));
	double c = fmax(fabs(a->centre[0]), fabs(a->centre[1]));
	double rmin = fmin(a->r0, a->r1), d, res;

	if (fmax(a->r0, a->r1) > SH2000_ARC_MAX_MM || c > SH2000_ARC_MAX_MM)
		return MSG(-ERANGE,
			   "arc radius %g mm or centre (%c%g,%c%g) is beyond %g mm: its points would round to more than a nanometre",
			   fmax(a->r0, a->r1), n[a->first], a->centre[0],
			   n[a->second], a->centre[1], SH2000_ARC_MAX_MM);
	if (full)
		return 0;
	d = remainder(atan2(e[1] - a->centre[1], e[0] - a->centre[0]) -
		      atan2(s[1] - a->centre[1], s[0] - a->centre[0]),
		      2 * M_PI);
	res = 8 * DBL_EPSILON * (fmax(m, c) / rmin + M_PI);
	if (fabs(d) <= res)
		return MSG(-EINVAL,
			   "arc sweep cannot be resolved: the end is %.3g mm from the start on a radius of %g mm, within the rounding of the angles (a whole turn or nothing)",
			   hypot(e[0] - s[0], e[1] - s[1]), rmin);
	return 0;
}

int sh2000_arc_resolve(struct sh2000_arc *a, enum sh2000_plane plane,
		       const double start[SH2000_AXES],
		       const double end[SH2000_AXES], const double centre[2],
		       bool ccw, unsigned int turns, double tol_mm,
		       double same_mm, char *msg, size_t len)
{
	double s[2], e[2], abs_err, rel_err;
	const char *n = SH2000_AXIS_LETTERS;
	bool full;
	int r;

	memset(a, 0, sizeof(*a));
	if (sh2000_plane_axes(plane, &a->first, &a->second, &a->normal))
		return MSG(-EINVAL, "unknown plane %d", (int)plane);
	if (turns < 1)
		return MSG(-EINVAL, "an arc has at least 1 turn: got %u", turns);
	if (tol_mm <= 0)
		tol_mm = SH2000_ARC_CENTRE_TOL_MM;
	a->plane = plane;
	s[0] = start[a->first];
	s[1] = start[a->second];
	e[0] = end[a->first];
	e[1] = end[a->second];
	memcpy(a->centre, centre, sizeof(a->centre));
	a->r0 = hypot(s[0] - centre[0], s[1] - centre[1]);
	a->r1 = hypot(e[0] - centre[0], e[1] - centre[1]);
	if (!isfinite(a->r0) || !isfinite(a->r1))
		return MSG(-ERANGE, "arc geometry is not finite");
	if (a->r0 < SH2000_ARC_RADIUS_TOL_MM || a->r1 < SH2000_ARC_RADIUS_TOL_MM)
		return MSG(-EINVAL, "zero-radius arc: r1=%.4f mm r2=%.4f mm",
			   a->r0, a->r1);
	abs_err = fabs(a->r0 - a->r1);
	rel_err = abs_err / fmax(a->r0, a->r1);
	if (abs_err > 100 * tol_mm ||
	    (abs_err > tol_mm && rel_err > SH2000_ARC_SPIRAL_REL_TOL))
		return MSG(-EINVAL,
			   "radius to end of arc differs from radius to start: start=(%c%.4f,%c%.4f) centre=(%c%.4f,%c%.4f) end=(%c%.4f,%c%.4f) r1=%.4f r2=%.4f mm (allowed: %.4f mm, or %.1f%% of the radius up to %.4f mm)",
			   n[a->first], s[0], n[a->second], s[1],
			   n[a->first], centre[0], n[a->second], centre[1],
			   n[a->first], e[0], n[a->second], e[1], a->r0, a->r1,
			   tol_mm, SH2000_ARC_SPIRAL_REL_TOL * 100, 100 * tol_mm);
	full = hypot(e[0] - s[0], e[1] - s[1]) < fmax(same_mm, 1e-9);
	r = check_resolvable(a, s, e, full, msg, len);
	if (r)
		return r;
	a->ccw = ccw;
	a->turns = turns;
	fit_circle(a, s, e, same_mm);
	a->th0 = atan2(s[1] - centre[1], s[0] - centre[0]);
	a->sweep = sweep_of(a->th0, atan2(e[1] - centre[1], e[0] - centre[0]),
			    ccw, turns, full);
	return 0;
}

void sh2000_arc_point(const struct sh2000_arc *a,
		      const double start[SH2000_AXES],
		      const double end[SH2000_AXES], double f,
		      double out[SH2000_AXES])
{
	double th = a->th0 + f * a->sweep, r = a->r0 + f * (a->r1 - a->r0);
	unsigned int i;

	for (i = 0; i < SH2000_AXES; i++)
		out[i] = start[i] + f * (end[i] - start[i]);
	out[a->first] = a->centre[0] + r * cos(th);
	out[a->second] = a->centre[1] + r * sin(th);
}
