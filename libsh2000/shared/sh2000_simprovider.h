/* SPDX-License-Identifier: MIT */
/*
 * Private contract between libsh2000 and libsh2000-sim: how the device
 * library gets a simulated card for the `sim` device string without
 * linking the card model. Not installed; both libraries come from one
 * source tree and the abi number guards a mismatched pair.
 */
#ifndef SH2000_SIMPROVIDER_H
#define SH2000_SIMPROVIDER_H

#include <stddef.h>

#include "sh2000/sh2000.h"

#define SH2000_SIM_SONAME		"libsh2000-sim.so.0"
#define SH2000_SIM_PROVIDER_SYMBOL	"sh2000_sim_provider_v1"
#define SH2000_SIM_PROVIDER_ABI		1u

struct sh2000_sim_provider {
	unsigned int abi;	/* SH2000_SIM_PROVIDER_ABI */
	/* A fresh card model with the documented defaults in virtual time,
	 * behind four registers: *p is filled and owns the model. */
	int (*open_ports)(struct sh2000_ports *p, char *msg, size_t len);
};

#endif /* SH2000_SIMPROVIDER_H */
