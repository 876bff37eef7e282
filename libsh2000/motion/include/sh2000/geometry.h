/* SPDX-License-Identifier: MIT */
/*
 * libsh2000-motion's geometry: the one definition of planes and their axis
 * order, of arcs from a centre or a radius (with LinuxCNC's tolerance
 * rule), and of NURBS evaluation. The program readers and the planner both
 * use it, so a program and its plan can never disagree about a curve.
 *
 * Coordinates are mm on the card's four linear axes X Y Z A (index 0..3).
 * Nothing here allocates or has state.
 */
#ifndef SH2000_GEOMETRY_H
#define SH2000_GEOMETRY_H

#include <stdbool.h>
#include <stddef.h>

#include "sh2000/card.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- planes ---------------------------------------------------------------- */

/*
 * The plane of an arc, numbered as the G-code that selects it. Its first
 * and second axes and its normal form a right-handed set, as in RS274NGC:
 * G17 X,Y (normal Z), G18 Z,X (normal Y), G19 Y,Z (normal X). An arc is
 * counter-clockwise (G3) when it turns from the first axis towards the
 * second, seen from the positive normal; the same rule in every plane.
 */
enum sh2000_plane {
	SH2000_PLANE_XY = 17,
	SH2000_PLANE_XZ = 18,
	SH2000_PLANE_YZ = 19,
};

/* The axes of a plane: 0, or -EINVAL for an unknown plane. */
int sh2000_plane_axes(enum sh2000_plane plane, unsigned int *first,
		      unsigned int *second, unsigned int *normal);
/* "XY", "XZ", "YZ"; "?" for an unknown plane. */
const char *sh2000_plane_name(enum sh2000_plane plane);

/* ---- arcs ------------------------------------------------------------------ */

/*
 * LinuxCNC's arc tolerances (rs274ngc: RADIUS_TOLERANCE_*, CENTER_ARC_RADIUS_
 * TOLERANCE_*, SPIRAL_RELATIVE_TOLERANCE): the smallest radius and the reach
 * allowance of a radius-form arc; the default allowed difference of start
 * and end radius of a centre-form arc in mm and in inch programs; and the
 * relative difference that is always allowed up to 100 times that.
 */
#define SH2000_ARC_RADIUS_TOL_MM	(0.00005 * 25.4)
#define SH2000_ARC_CENTRE_TOL_MM	(2 * 0.01 * 1.41421356237309504880)
#define SH2000_ARC_CENTRE_TOL_INCH_MM	(2 * 0.001 * 1.41421356237309504880 * 25.4)
#define SH2000_ARC_SPIRAL_REL_TOL	0.001

/*
 * The largest radius and centre coordinate, in mm, of an arc the geometry
 * resolves: a point of an arc is computed as centre + r (cos, sin), which
 * rounds by a few units of the last place of |centre| + r; below 1e8 mm
 * that is under 0.4 nm (8 DBL_EPSILON (|centre| + r)), a small part of any
 * card's count, and far beyond any machine's travel. Beyond it the sweep
 * and the points round to millimetres (R1e18 between two points 10 mm
 * apart rounds its sweep to nothing), so such an arc is refused.
 */
#define SH2000_ARC_MAX_MM		1e8

/*
 * An arc (or a helix) in a plane, resolved: everything a reader checks and
 * a planner needs. Plane coordinates are (first, second) of the plane.
 */
struct sh2000_arc {
	enum sh2000_plane plane;
	unsigned int first, second, normal;	/* axis indices */
	double centre[2];	/* as programmed */
	double r0, r1;		/* centre to start, centre to end */
	/*
	 * A true circle through both ends: the point of the perpendicular
	 * bisector of start and end nearest to the programmed centre, and
	 * its radius (the programmed centre for a full circle).
	 */
	double fit_centre[2];
	double fit_radius;
	double th0;		/* angle of the start seen from the centre */
	/* signed angle, counter-clockwise positive, with the extra turns */
	double sweep;
	bool ccw;
	unsigned int turns;	/* 1: the programmed arc, +1 per full turn */
};

/*
 * The centre of a radius-form arc (RS274NGC's R word) from start s and end
 * e in plane coordinates: r > 0 the arc of at most 180 degrees, r < 0 the
 * longer one. 0, or -EINVAL with the reason in msg (end == start, radius
 * too small to reach the end, radius beyond SH2000_ARC_MAX_MM).
 */
int sh2000_arc_centre_from_radius(const double s[2], const double e[2],
				  double r, bool ccw, double centre[2],
				  char *msg, size_t len);

/*
 * Resolve an arc from start to end (4 axes) around centre (plane
 * coordinates). turns >= 1; an end within same_mm of the start in the
 * plane is a full circle. The radii must agree by LinuxCNC's rule with
 * tol_mm (0: SH2000_ARC_CENTRE_TOL_MM): an error above 100 * tol_mm, or
 * above tol_mm and SH2000_ARC_SPIRAL_REL_TOL of the radius at once. An arc
 * that cannot be resolved is refused: a radius or centre beyond
 * SH2000_ARC_MAX_MM, or an end that is not the start (beyond same_mm) but
 * whose angle from the start is within the rounding of the two angles
 * (then the sweep could be nothing or a whole turn). 0, or -EINVAL/-ERANGE
 * with the reason in msg.
 */
int sh2000_arc_resolve(struct sh2000_arc *arc, enum sh2000_plane plane,
		       const double start[SH2000_AXES],
		       const double end[SH2000_AXES], const double centre[2],
		       bool ccw, unsigned int turns, double tol_mm,
		       double same_mm, char *msg, size_t len);

/* The point at fraction f (0..1) of the sweep: the radius changes linearly
 * from r0 to r1 (a programmed spiral), the axes outside the plane move
 * linearly (a helix). */
void sh2000_arc_point(const struct sh2000_arc *arc,
		      const double start[SH2000_AXES],
		      const double end[SH2000_AXES], double f,
		      double out[SH2000_AXES]);

/* ---- NURBS ----------------------------------------------------------------- */

#define SH2000_NURBS_MAX_DEGREE	31

/*
 * A non-uniform rational B-spline of the given degree over the 4 axes (a
 * view: the arrays belong to whoever made it):
 * npoints control points, npoints weights (> 0; NULL: all 1) and
 * npoints + degree + 1 non-decreasing knots. The curve runs over
 * knots[degree] .. knots[npoints].
 */
struct sh2000_nurbs {
	unsigned int degree;
	size_t npoints;
	const double (*points)[SH2000_AXES];
	const double *weights;
	const double *knots;
};

/*
 * Structure check: degree 1..SH2000_NURBS_MAX_DEGREE, enough points,
 * finite positive weights, finite points and knots, knots not decreasing,
 * no interior knot repeated more than degree times, a non-empty domain.
 * 0, or -EINVAL/-ERANGE with what is wrong in msg, naming the field as
 * "points[i]", "weights[i]", "knots[i]" or "degree".
 */
int sh2000_nurbs_check(const struct sh2000_nurbs *n, char *msg, size_t len);

/* The domain's ends. */
double sh2000_nurbs_umin(const struct sh2000_nurbs *n);
double sh2000_nurbs_umax(const struct sh2000_nurbs *n);

/*
 * The curve and its first and second derivatives with respect to u at u
 * (clamped to the domain). d1 and d2 may be NULL. The curve must have
 * passed sh2000_nurbs_check().
 */
void sh2000_nurbs_eval(const struct sh2000_nurbs *n, double u,
		       double c[SH2000_AXES], double d1[SH2000_AXES],
		       double d2[SH2000_AXES]);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_GEOMETRY_H */
