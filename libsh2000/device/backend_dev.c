/* SPDX-License-Identifier: MIT */
/*
 * /dev/sh2000-N: the kernel driver does the seeking (the same
 * sh2000_seek_plan()); the file is the RAM, word i at byte 2*i, LE. Also
 * what the driver says about itself (sh2000_driver_info()), so that no
 * program above the library needs the driver's headers.
 */
#include <endian.h>
#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <linux/types.h>
#include "uapi/sh2000.h"

#include "sh2000_internal.h"

/* The backend's own state: the open node. */
struct dev_priv {
	int fd;
};

static int dev_fd(const struct sh2000 *h)
{
	return ((const struct dev_priv *)h->priv)->fd;
}

static int dev_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf)
{
	size_t len = 2u * n, done = 0;
	unsigned int i;

	while (done < len) {
		ssize_t r = pread(dev_fd(h), (char *)buf + done, len - done,
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
		ssize_t r = pwrite(dev_fd(h), (char *)le + done, len - done,
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

	if (ioctl(dev_fd(h), SH2000_IOC_GET_COUNTERS, &k) < 0)
		return sh2000_fail(h, -errno, "SH2000_IOC_GET_COUNTERS: %s",
				   strerror(errno));
	c->clears = k.clears;
	c->increments = k.increments;
	c->data_reads = k.data_reads;
	c->data_writes = k.data_writes;
	c->position = k.position;
	return 0;
}

/* A character device: the lock file is named after its numbers, whatever
 * path opened it; a plain file (tests) is nobody else's. */
static int dev_lock_id(struct sh2000 *h, char *id, size_t len)
{
	struct stat sb;

	if (fstat(dev_fd(h), &sb) < 0 || !S_ISCHR(sb.st_mode))
		return 0;
	snprintf(id, len, "dev-%u-%u", major(sb.st_rdev), minor(sb.st_rdev));
	return 1;
}

static void dev_close(struct sh2000 *h)
{
	struct dev_priv *d = h->priv;

	if (d->fd >= 0)
		close(d->fd);
	d->fd = -1;
}

static const struct sh2000_backend dev_backend = {
	.kind = SH2000_BACKEND_DEV,
	.read = dev_read,
	.write = dev_write,
	.counters = dev_counters,
	.lock_id = dev_lock_id,
	.close = dev_close,
};

/* The group the udev rule gives the nodes to (udev/60-sh2000.rules). */
#define DEV_GROUP	"sh2000"
#define DEV_RULE	"60-sh2000.rules"

static int in_group(gid_t gid)
{
	gid_t *list;
	int n, i, found = getegid() == gid;

	n = getgroups(0, NULL);
	list = n > 0 ? calloc((size_t)n, sizeof(*list)) : NULL;
	if (list && getgroups(n, list) == n)
		for (i = 0; i < n; i++)
			found |= list[i] == gid;
	free(list);
	return found;
}

/* The name of group gid in buf (its number if it has none). */
static const char *group_name(gid_t gid, char *buf, size_t len)
{
	struct group gr, *g = NULL;
	char tmp[1024];

	if (getgrgid_r(gid, &gr, tmp, sizeof(tmp), &g) == 0 && g)
		snprintf(buf, len, "%s", g->gr_name);
	else
		snprintf(buf, len, "%u", (unsigned int)gid);
	return buf;
}

/* Why a node cannot be opened for lack of permission: what the udev rule
 * should have done and what is missing. */
static void access_hint(const char *path, char *buf, size_t len)
{
	struct group gr, *g = NULL;
	char grbuf[2048], owner[64];
	struct stat sb;

	if (stat(path, &sb) < 0) {
		snprintf(buf, len, " (the udev rule " DEV_RULE " gives the card to group " DEV_GROUP ")");
		return;
	}
	if (getgrnam_r(DEV_GROUP, &gr, grbuf, sizeof(grbuf), &g) || !g)
		snprintf(buf, len,
			 " (the udev rule " DEV_RULE " gives the card to group " DEV_GROUP ", and there is no group " DEV_GROUP ": sudo groupadd --system " DEV_GROUP ", then reload the rule; docs/driver.md)");
	else if (sb.st_gid != g->gr_gid)
		snprintf(buf, len,
			 " (it is group %s, mode %04o, not group " DEV_GROUP ": the udev rule " DEV_RULE " is not installed or has not run; docs/driver.md)",
			 group_name(sb.st_gid, owner, sizeof(owner)),
			 (unsigned int)(sb.st_mode & 07777));
	else if (!in_group(g->gr_gid))
		snprintf(buf, len,
			 " (it belongs to group " DEV_GROUP " (udev rule " DEV_RULE ") and this user is not in it: sudo usermod -aG " DEV_GROUP " $USER, then log in again)");
	else
		snprintf(buf, len,
			 " (group " DEV_GROUP " (udev rule " DEV_RULE ") has mode %04o on it)",
			 (unsigned int)(sb.st_mode & 07777));
}

int sh2000_dev_open(struct sh2000 *h, const char *path, char *msg,
		    size_t len)
{
	struct sh2000_info info;
	char hint[320] = "";
	int fd, e;

	fd = open(path, O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		e = errno;
		if (e == EACCES || e == EPERM)
			access_hint(path, hint, sizeof(hint));
		else if (e == ENOENT)
			snprintf(hint, sizeof(hint), " (is sh2000.ko loaded?)");
		return sh2000_msg(msg, len, -e, "%s: cannot open: %s%s", path,
				  strerror(e), hint);
	}
	if (ioctl(fd, SH2000_IOC_GET_INFO, &info) < 0) {
		e = errno;
		close(fd);
		return sh2000_msg(msg, len, e == ENOTTY ? -ENODEV : -e,
				  "%s: not an sh2000 device (GET_INFO: %s)",
				  path, strerror(e));
	}
	if (info.abi_version != SH2000_ABI_VERSION ||
	    info.ram_words != SH2000_RAM_WORDS) {
		close(fd);
		return sh2000_msg(msg, len, -EPROTO,
				  "%s: driver ABI %u with %u RAM words; library expects ABI %u with %u",
				  path, info.abi_version, info.ram_words,
				  SH2000_ABI_VERSION, SH2000_RAM_WORDS);
	}
	h->priv = calloc(1, sizeof(struct dev_priv));
	if (!h->priv) {
		close(fd);
		return sh2000_msg(msg, len, -ENOMEM, "%s: out of memory", path);
	}
	((struct dev_priv *)h->priv)->fd = fd;
	h->be = &dev_backend;
	return 0;
}

int sh2000_driver_info(struct sh2000 *h, char *version, size_t len,
		       unsigned int *abi, unsigned int *flags)
{
	struct sh2000_info info;
	int e;

	if (h->be != &dev_backend || dev_fd(h) < 0)
		return sh2000_fail(h, -ENODEV, "%s: no kernel driver behind this device",
				   h->device);
	memset(&info, 0, sizeof(info));
	if (ioctl(dev_fd(h), SH2000_IOC_GET_INFO, &info) < 0) {
		e = errno;
		return sh2000_fail(h, -e, "%s: GET_INFO: %s", h->device,
				   strerror(e));
	}
	if (version && len)
		snprintf(version, len, "%.*s", (int)sizeof(info.driver_version),
			 info.driver_version);
	if (abi)
		*abi = info.abi_version;
	if (flags)
		*flags = (info.flags & SH2000_INFO_SIMULATED) ?
			 SH2000_DRIVER_SIMULATED : 0;
	return 0;
}
