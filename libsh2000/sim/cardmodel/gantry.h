/* SPDX-License-Identifier: MIT */
/*
 * A gantry behind the card (gantry.c): two axes' plants joined by a beam
 * of finite yaw stiffness, with a carriage whose position along the beam
 * shares its mass between them. Only the board and the tests use it: the
 * firmware sees the two encoders, never the beam.
 */
#ifndef SH2000_GANTRY_H
#define SH2000_GANTRY_H

#include "plant.h"

struct sh2000_gantry {
	int on;
	struct sh2000_gantry_config cfg;
};

/* 0 when cfg describes a gantry the model can run, else -22. */
int sh2000_gantry_check(const struct sh2000_gantry_config *cfg);
/* 1 when axis is one of the beam's two sides. */
int sh2000_gantry_side(const struct sh2000_gantry *g, unsigned int axis);
/* Integrates T seconds of both sides with their DAC voltages held; the
 * carriage's plant is read where it is (NULL: at carriage_at0_mm). The
 * index edges either side passes are kept as plant_step keeps them. */
void sh2000_gantry_step(const struct sh2000_gantry *g, struct sh2000_plant *pa,
			struct sh2000_plant *pb,
			const struct sh2000_plant *carriage, double va,
			double vb, double T);

#endif /* SH2000_GANTRY_H */
