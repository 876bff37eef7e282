/* SPDX-License-Identifier: MIT */
/*
 * The shared-memory object that plays the dual-port RAM for `sim:NAME`:
 * /sh2000-NAME, one struct sh2000_shm. The server (libsh2000-sim's server.c) creates
 * it and runs the firmware on ram[]; hosts (libsh2000's backend_shm.c) map it and
 * touch ram[] only with 16-bit atomic accesses, as on the real RAM. The
 * host's FPGA address counter stays in the host's handle.
 */
#ifndef SH2000_SHM_H
#define SH2000_SHM_H

#include <stdint.h>

#include "sh2000_hw.h"

#define SH2000_SHM_MAGIC	0x53483253484d3031ull	/* "SH2SHM01" */
#define SH2000_SHM_LAYOUT	1u
#define SH2000_SHM_PREFIX	"/sh2000-"
#define SH2000_SHM_NAME_MAX	64

struct sh2000_shm {
	uint64_t magic;		/* SH2000_SHM_MAGIC once ram[] is ready */
	uint32_t layout;	/* SH2000_SHM_LAYOUT */
	int32_t owner_pid;	/* server process */
	uint64_t servo_period_ns;
	uint64_t cycles;	/* servo cycles run (server writes) */
	uint32_t running;	/* 1 while the server runs cycles */
	uint32_t reserved[9];
	uint16_t ram[SH2000_RAM_WORDS];
};

#endif /* SH2000_SHM_H */
