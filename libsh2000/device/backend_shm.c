/* SPDX-License-Identifier: MIT */
/*
 * sim:NAME: a card model served by another process (sh2000-sim, through
 * libsh2000-sim's server.c) whose
 * shared memory plays the dual-port RAM; real time. The FPGA side (the
 * address counter) is emulated here, so port-cycle counts are those of
 * the real card.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sh2000_internal.h"

static void shm_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	sh2000_fpga_out(&h->fpga, reg, v);
}

static uint16_t shm_in(struct sh2000 *h, unsigned int reg)
{
	return sh2000_fpga_in(&h->fpga, reg);
}

static void shm_close(struct sh2000 *h)
{
	if (h->shm)
		munmap(h->shm, sizeof(*h->shm));
	h->shm = NULL;
}

static const struct sh2000_backend shm_backend = {
	.kind = SH2000_BACKEND_SHM,
	.port_out = shm_out,
	.port_in = shm_in,
	.counters = sh2000_bus_counters,
	.close = shm_close,
};

int sh2000_shm_open(struct sh2000 *h, const char *name, char *msg,
		    size_t len)
{
	char path[SH2000_SHM_NAME_MAX + 16];
	struct stat sb;
	void *m;
	int fd, e;

	if (!*name || strlen(name) > SH2000_SHM_NAME_MAX || strchr(name, '/'))
		return sh2000_msg(msg, len, -EINVAL,
				  "sim:%s: bad name (1..%d characters, no '/')",
				  name, SH2000_SHM_NAME_MAX);
	snprintf(path, sizeof(path), SH2000_SHM_PREFIX "%s", name);
	fd = shm_open(path, O_RDWR, 0);
	if (fd < 0) {
		e = errno;
		return sh2000_msg(msg, len, -e, "sim:%s: no card served at %s: %s%s",
				  name, path, strerror(e),
				  e == ENOENT ? " (start sh2000-sim first)" : "");
	}
	if (fstat(fd, &sb) < 0 || (size_t)sb.st_size < sizeof(struct sh2000_shm)) {
		close(fd);
		return sh2000_msg(msg, len, -EPROTO,
				  "sim:%s: %s is not an sh2000 card (size)",
				  name, path);
	}
	m = mmap(NULL, sizeof(struct sh2000_shm), PROT_READ | PROT_WRITE,
		 MAP_SHARED, fd, 0);
	e = errno;
	close(fd);
	if (m == MAP_FAILED)
		return sh2000_msg(msg, len, -e, "sim:%s: mmap: %s", name,
				  strerror(e));
	h->shm = m;
	if (__atomic_load_n(&h->shm->magic, __ATOMIC_ACQUIRE) != SH2000_SHM_MAGIC ||
	    h->shm->layout != SH2000_SHM_LAYOUT) {
		shm_close(h);
		return sh2000_msg(msg, len, -EPROTO,
				  "sim:%s: %s is not an sh2000 card (magic/layout)",
				  name, path);
	}
	if (kill(h->shm->owner_pid, 0) < 0 && errno == ESRCH) {
		int pid = h->shm->owner_pid;

		shm_close(h);
		return sh2000_msg(msg, len, -ESRCH,
				  "sim:%s: server (pid %d) is gone", name, pid);
	}
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	sh2000_fpga_init(&h->fpga, h->shm->ram);
	h->be = &shm_backend;
	return 0;
}
