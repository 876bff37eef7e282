/* SPDX-License-Identifier: GPL-2.0 WITH Linux-syscall-note */
/*
 * User-space ABI of the sh2000 driver: the ioctls of /dev/sh2000-N.
 *
 * This is the only definition of the ABI: the driver, libsh2000, the tools
 * and the tests all include this file. Every structure uses fixed-width
 * fields and is laid out so that 32-bit and 64-bit callers see the same
 * size and offsets (no compat_ioctl translation is needed).
 *
 * File semantics (see docs/driver.md): the file is the card's 2048-byte
 * dual-port RAM, word i at byte 2*i, little-endian. Offsets and lengths must
 * be even.
 */
#ifndef _UAPI_LINUX_SH2000_H
#define _UAPI_LINUX_SH2000_H

#include <linux/ioctl.h>
#include <linux/types.h>

/* Bumped on any incompatible change of the ioctls or file semantics. */
#define SH2000_ABI_VERSION	1

#define SH2000_IOC_MAGIC	0xB7

/* struct sh2000_info.flags */
#define SH2000_INFO_SIMULATED	0x1U		/* bound to an sh2000_sim card */

#define SH2000_VERSION_LEN	16

/**
 * struct sh2000_info - what SH2000_IOC_GET_INFO reports about a card
 * @abi_version:	SH2000_ABI_VERSION of the running driver
 * @base:		I/O base address (0 for a simulated card)
 * @ram_bytes:		size of the dual-port RAM in bytes (2048)
 * @ram_words:		size of the dual-port RAM in 16-bit words (1024)
 * @index:		N of /dev/sh2000-N
 * @flags:		SH2000_INFO_* bits
 * @driver_version:	NUL-terminated driver version string
 * @reserved:		zero; room for later fields
 */
struct sh2000_info {
	__u32 abi_version;
	__u32 base;
	__u32 ram_bytes;
	__u32 ram_words;
	__u32 index;
	__u32 flags;
	char driver_version[SH2000_VERSION_LEN];
	__u32 reserved[8];
};

/* struct sh2000_counters.position when the counter position is not known */
#define SH2000_POSITION_UNKNOWN	0xffffffffU

/**
 * struct sh2000_counters - port cycles issued to a card since it came up
 * @clears:		writes to the address-clear register
 * @increments:		writes to the address-increment register
 * @data_reads:		16-bit reads of the data register
 * @data_writes:	16-bit writes of the data register
 * @position:		where the driver knows the address counter to be,
 *			or SH2000_POSITION_UNKNOWN
 * @reserved:		zero
 */
struct sh2000_counters {
	__u64 clears;
	__u64 increments;
	__u64 data_reads;
	__u64 data_writes;
	__u32 position;
	__u32 reserved;
};

/* Read the card's identity. */
#define SH2000_IOC_GET_INFO		_IOR(SH2000_IOC_MAGIC, 0, struct sh2000_info)
/* Read the port-cycle counters (also in sysfs). */
#define SH2000_IOC_GET_COUNTERS		_IOR(SH2000_IOC_MAGIC, 1, struct sh2000_counters)
/*
 * Forget the address counter position: the next access clears the counter
 * first. Use after something else (a card reset, a debugger) moved it.
 */
#define SH2000_IOC_FORGET_POSITION	_IO(SH2000_IOC_MAGIC, 2)

#endif /* _UAPI_LINUX_SH2000_H */
