/* SPDX-License-Identifier: GPL-2.0 OR MIT */
/*
 * The SH-2000TH card as this project assumes it: the one place that holds the
 * choices docs/card.md records where the card's
 * paper is silent. A different card revision changes this file only.
 *
 * Included by the kernel driver, the simulated card module, libsh2000 and
 * its card model, so it uses no kernel or libc types.
 */
#ifndef SH2000_HW_H
#define SH2000_HW_H

/*
 * ISA base address: A2..A9 are compared by a 74LS688, so the base is 4-byte
 * aligned and the window is 4 ports. It is set by switches on the card and
 * given by the user; ISA space is never probed.
 */
#define SH2000_IO_MIN		0x100
#define SH2000_IO_MAX		0x3fc
#define SH2000_IO_ALIGN		4
#define SH2000_IO_EXTENT	4

/* Register offsets from the base (A0/A1 select them in the FPGA). */
#define SH2000_REG_ADDR_CLEAR	0	/* write (value ignored): counter = 0 */
#define SH2000_REG_ADDR_INC	1	/* write (value ignored): counter += 1 */
#define SH2000_REG_DATA		2	/* 16-bit read/write of RAM[counter] */
#define SH2000_REG_SPARE	3	/* decoded but unused by the protocol */

/*
 * Dual-port RAM seen from the host: 1024 words of 16 bits (2 KiB). The
 * address counter has 10 bits and wraps from 1023 to 0. A data access does
 * not move the counter.
 */
#define SH2000_RAM_WORDS	1024U
#define SH2000_RAM_BYTES	(2U * SH2000_RAM_WORDS)
#define SH2000_ADDR_MASK	(SH2000_RAM_WORDS - 1U)

/* Estimate used by docs and the card model: one ISA I/O cycle is ~1 us. */
#define SH2000_PORT_CYCLE_NS	1000U

static inline int sh2000_io_base_valid(unsigned long base)
{
	return base >= SH2000_IO_MIN && base <= SH2000_IO_MAX &&
	       base % SH2000_IO_ALIGN == 0;
}

#endif /* SH2000_HW_H */
