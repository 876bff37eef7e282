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
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sh2000_fpga.h"
#include "sh2000_internal.h"
#include "sh2000_shm.h"

/* The backend's own state: the served RAM and the FPGA, emulated on this
 * side. */
struct shm_priv {
	struct sh2000_shm *shm;
	struct sh2000_fpga fpga;
};

static struct shm_priv *shm_priv(const struct sh2000 *h)
{
	return h->priv;
}

static void shm_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	sh2000_fpga_out(&shm_priv(h)->fpga, reg, v);
}

static uint16_t shm_in(struct sh2000 *h, unsigned int reg)
{
	return sh2000_fpga_in(&shm_priv(h)->fpga, reg);
}

static void shm_close(struct sh2000 *h)
{
	struct shm_priv *p = shm_priv(h);

	if (p->shm)
		munmap(p->shm, sizeof(*p->shm));
	p->shm = NULL;
}

/* Every program using the card served under this name shares it. */
static int shm_lock_id(struct sh2000 *h, char *id, size_t len)
{
	snprintf(id, len, "shm-%s", h->device + 4);
	return 1;
}

static const struct sh2000_backend shm_backend = {
	.kind = SH2000_BACKEND_SHM,
	.port_out = shm_out,
	.port_in = shm_in,
	.counters = sh2000_bus_counters,
	.lock_id = shm_lock_id,
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
	h->priv = calloc(1, sizeof(struct shm_priv));
	if (!h->priv) {
		munmap(m, sizeof(struct sh2000_shm));
		return sh2000_msg(msg, len, -ENOMEM, "sim:%s: out of memory",
				  name);
	}
	shm_priv(h)->shm = m;
	if (__atomic_load_n(&shm_priv(h)->shm->magic, __ATOMIC_ACQUIRE) !=
	    SH2000_SHM_MAGIC ||
	    shm_priv(h)->shm->layout != SH2000_SHM_LAYOUT) {
		shm_close(h);
		return sh2000_msg(msg, len, -EPROTO,
				  "sim:%s: %s is not an sh2000 card (magic/layout)",
				  name, path);
	}
	if (kill(shm_priv(h)->shm->owner_pid, 0) < 0 && errno == ESRCH) {
		int pid = shm_priv(h)->shm->owner_pid;

		shm_close(h);
		return sh2000_msg(msg, len, -ESRCH,
				  "sim:%s: server (pid %d) is gone", name, pid);
	}
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	sh2000_fpga_init(&shm_priv(h)->fpga, shm_priv(h)->shm->ram);
	h->be = &shm_backend;
	return 0;
}
