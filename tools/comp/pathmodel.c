// SPDX-License-Identifier: MIT
/*
 * The simulated machine's model as the path check uses it to take its
 * error apart (calib.h, struct cal_path): the carriages from the
 * interferometer's reading, the tool where a perfect servo on a scale
 * read without quantisation would put it for a set-point, and the
 * distance of a point from a program's straight segment.
 */
#include <math.h>

#include "calib.h"

/* The carriages with the tool at tool[] (the geometry's errors are
 * microns: a few fixed-point steps reach the double's resolution). */
void cal_model_carriage(const struct sh2000_geometry *g,
			const double tool[SH2000_AXES], double x[SH2000_AXES])
{
	double t[SH2000_AXES];
	unsigned int a, k;

	for (a = 0; a < SH2000_AXES; a++)
		x[a] = tool[a];
	for (k = 0; k < 6; k++) {
		sh2000_geometry_tool(g, x, t);
		for (a = 0; a < SH2000_AXES; a++)
			x[a] -= t[a] - tool[a];
	}
}

/* The carriage of axis a where its scale reads s mm (the scale's slope is
 * within 1e-3 of one). */
static double carriage_at_reading(const struct sh2000_geometry *g,
				  unsigned int a, double s)
{
	double x = s;
	unsigned int k;

	for (k = 0; k < 6; k++)
		x -= sh2000_geometry_scale(g, a, x) - s;
	return x;
}

/* The counter's offset from the scale's count (counter = floor(reading *
 * scale) + k): from a counter and the tool at the same instant. */
void cal_model_offset(const struct cal_sim *s, const double counter[SH2000_AXES],
		      const double tool[SH2000_AXES], double k[SH2000_AXES])
{
	double x[SH2000_AXES];
	unsigned int a;

	cal_model_carriage(&s->geom, tool, x);
	for (a = 0; a < SH2000_AXES; a++)
		k[a] = counter[a] -
		       floor(sh2000_geometry_scale(&s->geom, a, x[a]) * s->scale[a]);
}

/* Where the tool is when each axis' scale reads the middle of the count
 * of set-point sp (counts; the loop holds the counter, the floor of the
 * reading, on the set-point, so the reading dwells in that count). */
void cal_model_tool(const struct cal_sim *s, const double k[SH2000_AXES],
		    const double sp[SH2000_AXES], double tool[SH2000_AXES])
{
	double x[SH2000_AXES];
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		x[a] = carriage_at_reading(&s->geom, a,
					   (sp[a] - k[a] + 0.5) / s->scale[a]);
	sh2000_geometry_tool(&s->geom, x, tool);
}

/* The distance of p from the segment a-b (X, Y, Z) and, in perp, the part
 * of d that is square to the segment. */
double cal_model_segment(const double a[3], const double b[3],
			 const double p[3], const double d[3], double perp[3])
{
	double u[3], q[3], len2 = 0.0, t = 0.0, along = 0.0, dist = 0.0;
	unsigned int i;

	for (i = 0; i < 3; i++) {
		u[i] = b[i] - a[i];
		len2 += u[i] * u[i];
		t += (p[i] - a[i]) * u[i];
		along += d[i] * u[i];
	}
	t = len2 > 0.0 ? fmin(1.0, fmax(0.0, t / len2)) : 0.0;
	along = len2 > 0.0 ? along / len2 : 0.0;
	for (i = 0; i < 3; i++) {
		q[i] = p[i] - (a[i] + t * u[i]);
		dist += q[i] * q[i];
		perp[i] = d[i] - along * u[i];
	}
	return sqrt(dist);
}
