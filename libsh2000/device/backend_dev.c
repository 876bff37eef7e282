/* SPDX-License-Identifier: MIT */
/*
 * /dev/sh2000-N: the kernel driver does the seeking (the same
 * sh2000_seek_plan()); the file is the RAM, word i at byte 2*i, LE.
 */
#include <endian.h>
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/types.h>
#include "uapi/sh2000.h"

#include "sh2000_internal.h"

static int dev_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf)
{
	size_t len = 2u * n, done = 0;
	unsigned int i;

	while (done < len) {
		ssize_t r = pread(h->fd, (char *)buf + done, len - done,
				  (off_t)(2u * addr + done));

		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return sh2000_fail(h, -errno, "read of words %u..%u: %s",
					   addr, addr + n - 1, strerror(errno));
		if (r == 0)
			return sh2000_fail(h, -EIO, "short read at word %u",
					   addr);
		done += (size_t)r;
	}
	for (i = 0; i < n; i++)
		buf[i] = le16toh(buf[i]);
	return 0;
}

static int dev_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf)
{
	uint16_t le[SH2000_RAM_WORDS];
	size_t len = 2u * n, done = 0;
	unsigned int i;

	for (i = 0; i < n; i++)
		le[i] = htole16(buf[i]);
	while (done < len) {
		ssize_t r = pwrite(h->fd, (char *)le + done, len - done,
				   (off_t)(2u * addr + done));

		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return sh2000_fail(h, -errno, "write of words %u..%u: %s",
					   addr, addr + n - 1, strerror(errno));
		if (r == 0)
			return sh2000_fail(h, -EIO, "short write at word %u",
					   addr);
		done += (size_t)r;
	}
	return 0;
}

static int dev_counters(struct sh2000 *h, struct sh2000_port_counters *c)
{
	struct sh2000_counters k;

	if (ioctl(h->fd, SH2000_IOC_GET_COUNTERS, &k) < 0)
		return sh2000_fail(h, -errno, "SH2000_IOC_GET_COUNTERS: %s",
				   strerror(errno));
	c->clears = k.clears;
	c->increments = k.increments;
	c->data_reads = k.data_reads;
	c->data_writes = k.data_writes;
	c->position = k.position;
	return 0;
}

static void dev_close(struct sh2000 *h)
{
	if (h->fd >= 0)
		close(h->fd);
	h->fd = -1;
}

static const struct sh2000_backend dev_backend = {
	.kind = SH2000_BACKEND_DEV,
	.read = dev_read,
	.write = dev_write,
	.counters = dev_counters,
	.close = dev_close,
};

int sh2000_dev_open(struct sh2000 *h, const char *path, char *msg,
		    size_t len)
{
	struct sh2000_info info;
	int e;

	h->fd = open(path, O_RDWR | O_CLOEXEC);
	if (h->fd < 0) {
		e = errno;
		return sh2000_msg(msg, len, -e, "%s: cannot open: %s%s", path,
				  strerror(e),
				  e == ENOENT ? " (is sh2000.ko loaded?)" : "");
	}
	if (ioctl(h->fd, SH2000_IOC_GET_INFO, &info) < 0) {
		e = errno;
		close(h->fd);
		h->fd = -1;
		return sh2000_msg(msg, len, e == ENOTTY ? -ENODEV : -e,
				  "%s: not an sh2000 device (GET_INFO: %s)",
				  path, strerror(e));
	}
	if (info.abi_version != SH2000_ABI_VERSION ||
	    info.ram_words != SH2000_RAM_WORDS) {
		close(h->fd);
		h->fd = -1;
		return sh2000_msg(msg, len, -EPROTO,
				  "%s: driver ABI %u with %u RAM words; library expects ABI %u with %u",
				  path, info.abi_version, info.ram_words,
				  SH2000_ABI_VERSION, SH2000_RAM_WORDS);
	}
	h->be = &dev_backend;
	return 0;
}
