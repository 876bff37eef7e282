/* SPDX-License-Identifier: GPL-2.0 OR MIT */
/*
 * Shared by the in-VM test program and the driver benchmark: result lines,
 * counter snapshots and an independent model of the minimal port-cycle cost.
 *
 * The model is written from the card rules (docs/card.md), not from
 * driver/sh2000_seek.h, so that it checks the driver's seek logic instead of
 * repeating it: a clear costs 1 cycle, an increment 1, a data access 1; the
 * counter only goes forward (wrapping 1023 -> 0) or back to 0; no increment
 * follows the last word of a transfer; of two equally cheap ways the one
 * without a clear is taken.
 */
#ifndef SH2000_KTEST_H
#define SH2000_KTEST_H

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>

#include "sh2000_hw.h"
#include "uapi/sh2000.h"

#define RAMB	((long)SH2000_RAM_BYTES)
#define RAMW	((long)SH2000_RAM_WORDS)

/* Expected counter state of one card. pos < 0: position unknown. */
struct model {
	long pos;
	unsigned long long clears, incs, reads, writes;
};

static inline int get_counters(int fd, struct sh2000_counters *c)
{
	memset(c, 0, sizeof(*c));
	return ioctl(fd, SH2000_IOC_GET_COUNTERS, c);
}

static inline void model_from(struct model *m, const struct sh2000_counters *c)
{
	m->pos = c->position == SH2000_POSITION_UNKNOWN ? -1 : (long)c->position;
	m->clears = c->clears;
	m->incs = c->increments;
	m->reads = c->data_reads;
	m->writes = c->data_writes;
}

/* Cheapest way from the model's position to word t, by enumeration. */
static inline void model_seek(struct model *m, long t)
{
	long forward, via_clear = 1 + t;

	if (m->pos < 0) {
		m->clears++;
		m->incs += t;
	} else {
		/* only increments: t - pos, or through the 1023 -> 0 wrap */
		forward = t >= m->pos ? t - m->pos : RAMW - m->pos + t;
		if (forward <= via_clear) {
			m->incs += forward;
		} else {
			m->clears++;
			m->incs += t;
		}
	}
	m->pos = t;
}

/*
 * A valid (even) transfer of len bytes at byte offset off: what the driver
 * must return and what it costs. Returns the expected byte count, or
 * -ENOSPC for a write at the end.
 */
static inline long model_xfer(struct model *m, long off, long len, int write)
{
	long n;

	if (len == 0)
		return 0;
	if (off >= RAMB)
		return write ? -ENOSPC : 0;
	n = len < RAMB - off ? len : RAMB - off;
	model_seek(m, off / 2);
	if (write)
		m->writes += n / 2;
	else
		m->reads += n / 2;
	m->incs += n / 2 - 1;
	m->pos = off / 2 + n / 2 - 1;
	return n;
}

static inline unsigned long long model_total(const struct model *m)
{
	return m->clears + m->incs + m->reads + m->writes;
}

static inline unsigned long long counters_total(const struct sh2000_counters *c)
{
	return c->clears + c->increments + c->data_reads + c->data_writes;
}

#endif /* SH2000_KTEST_H */
