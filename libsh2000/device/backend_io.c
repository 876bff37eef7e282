/* SPDX-License-Identifier: MIT */
/*
 * io:0xNNN: the card's four ports from user space (ioperm, inw/outw).
 * Needs CAP_SYS_RAWIO; x86 only.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sh2000_internal.h"

#if defined(__x86_64__) || defined(__i386__)
#include <linux/capability.h>
#include <sys/io.h>
#include <sys/syscall.h>
#include <unistd.h>

/* The backend's own state: where the ports are. */
struct io_priv {
	unsigned long base;
};

static unsigned long io_base(const struct sh2000 *h)
{
	return ((const struct io_priv *)h->priv)->base;
}

static void io_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	if (reg == SH2000_REG_DATA)
		outw(v, (unsigned short)(io_base(h) + reg));
	else
		outb(0, (unsigned short)(io_base(h) + reg));
}

static uint16_t io_in(struct sh2000 *h, unsigned int reg)
{
	return inw((unsigned short)(io_base(h) + reg));
}

/*
 * The FPGA's address counter is one for every process doing port I/O on
 * these ports: a word transfer is one port sequence under the arbiter's
 * bus lock, and the counter is unknown after another process may have
 * moved it.
 */
static int io_bus_take(struct sh2000 *h)
{
	int r = sh2000_arb_bus_take(h);

	if (!r)
		h->bus.pos = SH2000_SEEK_UNKNOWN;
	return r;
}

static int io_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		   uint16_t *buf)
{
	int r = io_bus_take(h);

	if (!r)
		r = sh2000_bus_read(h, addr, n, buf);
	sh2000_arb_drop(h, SH2000_ARB_BUS);
	return r;
}

static int io_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		    const uint16_t *buf)
{
	int r = io_bus_take(h);

	if (!r)
		r = sh2000_bus_write(h, addr, n, buf);
	sh2000_arb_drop(h, SH2000_ARB_BUS);
	return r;
}

static void io_close(struct sh2000 *h)
{
	ioperm(io_base(h), SH2000_IO_EXTENT, 0);
}

/* Every program doing port I/O on these ports shares the lock file. */
static int io_lock_id(struct sh2000 *h, char *id, size_t len)
{
	snprintf(id, len, "io-0x%lx", io_base(h));
	return 1;
}

static const struct sh2000_backend io_backend = {
	.kind = SH2000_BACKEND_IO,
	.read = io_read,
	.write = io_write,
	.port_out = io_out,
	.port_in = io_in,
	.counters = sh2000_bus_counters,
	.lock_id = io_lock_id,
	.close = io_close,
};

static int has_rawio(void)
{
	struct __user_cap_header_struct hdr = {
		.version = _LINUX_CAPABILITY_VERSION_3, .pid = 0 };
	struct __user_cap_data_struct data[2];

	memset(data, 0, sizeof(data));
	if (syscall(SYS_capget, &hdr, data) < 0)
		return -1;
	return !!(data[CAP_SYS_RAWIO / 32].effective &
		  (1u << (CAP_SYS_RAWIO % 32)));
}
#endif

int sh2000_io_open(struct sh2000 *h, const char *spec, char *msg, size_t len)
{
	char *end;
	unsigned long base;

	/* hexadecimal with 0x only, as the switches and docs write a base:
	 * io:300 read as decimal would be port 0x12c, a valid base, and the
	 * port I/O would go to another board */
	errno = 0;
	base = strtoul(spec + 2, &end, 16);
	if (spec[0] != '0' || (spec[1] != 'x' && spec[1] != 'X') ||
	    !spec[2] || strspn(spec + 2, "0123456789abcdefABCDEF") != strlen(spec + 2) ||
	    errno || *end)
		return sh2000_msg(msg, len, -EINVAL,
				  "io:%s: not a port base: write it in hexadecimal with 0x, as the card's address switches give it (io:0x300)",
				  spec);
	if (!sh2000_io_base_valid(base))
		return sh2000_msg(msg, len, -EINVAL,
				  "io:%s: base 0x%lx invalid: must be %u-aligned in 0x%x..0x%x",
				  spec, base, SH2000_IO_ALIGN, SH2000_IO_MIN,
				  SH2000_IO_MAX);
#if defined(__x86_64__) || defined(__i386__)
	if (has_rawio() == 0)
		return sh2000_msg(msg, len, -EPERM,
				  "io:%s: direct port I/O needs CAP_SYS_RAWIO (run as root or setcap cap_sys_rawio+ep; or use /dev/sh2000-N)",
				  spec);
	if (ioperm(base, SH2000_IO_EXTENT, 1) < 0) {
		int e = errno;

		return sh2000_msg(msg, len, -e, "io:%s: ioperm: %s%s", spec,
				  strerror(e),
				  e == EPERM ? " (needs CAP_SYS_RAWIO)" : "");
	}
	h->priv = calloc(1, sizeof(struct io_priv));
	if (!h->priv) {
		ioperm(base, SH2000_IO_EXTENT, 0);
		return sh2000_msg(msg, len, -ENOMEM, "io:%s: out of memory",
				  spec);
	}
	((struct io_priv *)h->priv)->base = base;
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	h->be = &io_backend;
	return 0;
#else
	return sh2000_msg(msg, len, -EOPNOTSUPP,
			  "io:%s: direct port I/O exists on x86 only", spec);
#endif
}
