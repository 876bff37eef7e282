// SPDX-License-Identifier: MIT
/*
 * The machine's geometric errors (docs/cardmodel.md "Geometry"): what each
 * scale reads at its carriage (pitch error), and where the tool truly is
 * with the carriages where they are (squareness, straightness, flatness),
 * as a laser interferometer would measure it. The defaults are the
 * compensation issue's machine: about 10 um of pitch error over 300 mm,
 * 50 urad between X and Y, a few um of straightness and flatness.
 */
#include <math.h>
#include <string.h>

#include "sh2000/sh2000_cardsim.h"

void sh2000_geometry_none(struct sh2000_geometry *g)
{
	unsigned int a, k;

	memset(g, 0, sizeof(*g));
	for (a = 0; a < SH2000_AXES; a++)
		for (k = 0; k < SH2000_PITCH_TERMS; k++)
			g->pitch_period_mm[a][k] = 1.0;
	g->travel_lo_mm = 0.0;
	g->travel_hi_mm = 600.0;
}

/* Each axis: slope (mm/mm), then two periodic terms (amplitude mm, period
 * mm, phase rad). */
static const double pitch_default[SH2000_AXES][7] = {
	{ 30e-6, 0.8e-3, 25.0, 0.3, 0.3e-3, 12.5, 1.1 },
	{ -20e-6, 0.6e-3, 40.0, 1.7, 0.2e-3, 16.0, 0.2 },
	{ 15e-6, 0.5e-3, 20.0, 0.9, 0.0, 1.0, 0.0 },
	{ 10e-6, 0.3e-3, 30.0, 0.0, 0.0, 1.0, 0.0 },
};

void sh2000_geometry_default(struct sh2000_geometry *g)
{
	unsigned int a, k;

	sh2000_geometry_none(g);
	for (a = 0; a < SH2000_AXES; a++) {
		g->pitch_slope[a] = pitch_default[a][0];
		for (k = 0; k < SH2000_PITCH_TERMS; k++) {
			g->pitch_amp_mm[a][k] = pitch_default[a][1 + 3 * k];
			g->pitch_period_mm[a][k] = pitch_default[a][2 + 3 * k];
			g->pitch_phase[a][k] = pitch_default[a][3 + 3 * k];
		}
	}
	g->squareness_xy = 50e-6;
	g->straight_x_mm = 3e-3;
	g->straight_y_mm = -2e-3;
	g->flat_mm = 2e-3;
	g->flat_twist_mm = 1e-3;
}

double sh2000_geometry_scale(const struct sh2000_geometry *g, unsigned int a,
			     double x)
{
	double s = x + g->pitch_slope[a] * (x - g->pitch_ref_mm[a]);
	unsigned int k;

	for (k = 0; k < SH2000_PITCH_TERMS; k++)
		if (g->pitch_amp_mm[a][k] != 0.0)
			s += g->pitch_amp_mm[a][k] *
			     sin(2.0 * M_PI * x / g->pitch_period_mm[a][k] +
				 g->pitch_phase[a][k]);
	return s;
}

static double unit(const struct sh2000_geometry *g, double x)
{
	return (x - g->travel_lo_mm) / (g->travel_hi_mm - g->travel_lo_mm);
}

static double bow(const struct sh2000_geometry *g, double x)
{
	double u = unit(g, x);

	return 4.0 * u * (1.0 - u);
}

void sh2000_geometry_tool(const struct sh2000_geometry *g,
			  const double x[SH2000_AXES], double tool[SH2000_AXES])
{
	double sx = 2.0 * unit(g, x[0]) - 1.0, sy = 2.0 * unit(g, x[1]) - 1.0;

	tool[0] = x[0] + g->squareness_xy * x[1] + g->straight_y_mm * bow(g, x[1]);
	tool[1] = x[1] + g->straight_x_mm * bow(g, x[0]);
	tool[2] = x[2] + g->flat_mm * 0.5 * (bow(g, x[0]) + bow(g, x[1])) +
		  g->flat_twist_mm * sx * sy;
	tool[3] = x[3];
}
