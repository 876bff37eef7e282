/* SPDX-License-Identifier: MIT */
/* The backend ops table and the register-level bus. */
#ifndef SH2000_BACKEND_H
#define SH2000_BACKEND_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/sh2000.h"

struct sh2000;

/*
 * A backend moves whole word ranges itself (read/write: the kernel
 * driver; io:, which runs the bus under the arbiter's bus lock) or
 * offers only the four FPGA registers (sim, sim:NAME, struct
 * sh2000_ports), in which case the bus (bus.c) does the seeking with
 * sh2000_seek_plan(). Its own state is behind h->priv, seen by its file
 * alone.
 */
struct sh2000_backend {
	enum sh2000_backend_kind kind;
	int virtual_time;	/* waits advance the model, under the lock */
	int (*read)(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf);
	int (*write)(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf);
	void (*port_out)(struct sh2000 *h, unsigned int reg, uint16_t v);
	uint16_t (*port_in)(struct sh2000 *h, unsigned int reg);
	uint64_t (*now_ns)(struct sh2000 *h);
	void (*wait_ns)(struct sh2000 *h, uint64_t ns);
	int (*counters)(struct sh2000 *h, struct sh2000_port_counters *c);
	/* The name of the card's lock file, shared by every program that
	 * reaches the same card: 1 with id filled, 0 when nobody else can
	 * reach it (an in-process card, a plain file). */
	int (*lock_id)(struct sh2000 *h, char *id, size_t len);
	/* Undo the open; h->priv is freed after it by the handle. */
	void (*close)(struct sh2000 *h);
};

/* bus.c: port cycles and counter position of a register-level bus. */
struct sh2000_bus {
	unsigned int pos;	/* SH2000_SEEK_UNKNOWN until the first clear */
	uint64_t clears, increments, data_reads, data_writes;
};

#endif /* SH2000_BACKEND_H */
