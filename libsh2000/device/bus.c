/* SPDX-License-Identifier: MIT */
/*
 * The register-level bus of io:, sim and sim:NAME: the FPGA address
 * counter moved with the one seek logic (sh2000_seek.h), the same plan the
 * kernel driver follows, with lazy increments: a transfer of n words
 * leaves the counter on its last word.
 */
#include <errno.h>

#include "sh2000_internal.h"

static void bus_seek(struct sh2000 *h, unsigned int target)
{
	struct sh2000_seek s = sh2000_seek_plan(h->bus.pos, target);
	unsigned int i;

	if (s.clear) {
		h->be->port_out(h, SH2000_REG_ADDR_CLEAR, 0);
		h->bus.clears++;
	}
	for (i = 0; i < s.increments; i++)
		h->be->port_out(h, SH2000_REG_ADDR_INC, 0);
	h->bus.increments += s.increments;
	h->bus.pos = target & SH2000_ADDR_MASK;
}

static void bus_step(struct sh2000 *h)
{
	h->be->port_out(h, SH2000_REG_ADDR_INC, 0);
	h->bus.increments++;
	h->bus.pos = (h->bus.pos + 1) & SH2000_ADDR_MASK;
}

int sh2000_bus_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf)
{
	unsigned int i;

	if (!n)
		return 0;
	bus_seek(h, addr);
	for (i = 0; i < n; i++) {
		if (i)
			bus_step(h);
		buf[i] = h->be->port_in(h, SH2000_REG_DATA);
	}
	h->bus.data_reads += n;
	return 0;
}

int sh2000_bus_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf)
{
	unsigned int i;

	if (!n)
		return 0;
	bus_seek(h, addr);
	for (i = 0; i < n; i++) {
		if (i)
			bus_step(h);
		h->be->port_out(h, SH2000_REG_DATA, buf[i]);
	}
	h->bus.data_writes += n;
	return 0;
}

int sh2000_bus_counters(struct sh2000 *h, struct sh2000_port_counters *c)
{
	c->clears = h->bus.clears;
	c->increments = h->bus.increments;
	c->data_reads = h->bus.data_reads;
	c->data_writes = h->bus.data_writes;
	c->position = h->bus.pos;
	return 0;
}

/* sh2000.h's size of the RAM for programs above the library is the
 * register map's */
_Static_assert(SH2000_DPRAM_WORDS == SH2000_RAM_WORDS,
	       "SH2000_DPRAM_WORDS differs from driver/sh2000_hw.h");

int sh2000_rd(struct sh2000 *h, unsigned int addr, unsigned int n,
	      uint16_t *buf)
{
	if (addr >= SH2000_RAM_WORDS || n > SH2000_RAM_WORDS - addr)
		return -EINVAL;
	if (h->be->read)
		return h->be->read(h, addr, n, buf);
	return sh2000_bus_read(h, addr, n, buf);
}

int sh2000_wr(struct sh2000 *h, unsigned int addr, unsigned int n,
	      const uint16_t *buf)
{
	if (addr >= SH2000_RAM_WORDS || n > SH2000_RAM_WORDS - addr)
		return -EINVAL;
	if (h->be->write)
		return h->be->write(h, addr, n, buf);
	return sh2000_bus_write(h, addr, n, buf);
}
