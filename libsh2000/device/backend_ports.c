/* SPDX-License-Identifier: MIT */
/*
 * A card behind four registers that the caller supplies (struct
 * sh2000_ports): the simulated card of libsh2000-sim, a test's fake card,
 * or any other register-level model. The bus (bus.c) does the seeking, as
 * for io:. With SH2000_PORTS_F_VIRTUAL_TIME, waits advance the card's
 * clock under the handle's lock instead of sleeping.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "sh2000_internal.h"

/* The backend's own state is the caller's struct sh2000_ports, copied. */
static struct sh2000_ports *ports(const struct sh2000 *h)
{
	return h->priv;
}

static void ports_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	const struct sh2000_ports *p = ports(h);

	p->out(p->ctx, reg, v);
}

static uint16_t ports_in(struct sh2000 *h, unsigned int reg)
{
	const struct sh2000_ports *p = ports(h);

	return p->in(p->ctx, reg);
}

static uint64_t ports_now(struct sh2000 *h)
{
	const struct sh2000_ports *p = ports(h);

	return p->now_ns ? p->now_ns(p->ctx) : sh2000_mono_ns();
}

static void ports_wait(struct sh2000 *h, uint64_t ns)
{
	const struct sh2000_ports *p = ports(h);

	if (p->advance_ns)
		p->advance_ns(p->ctx, ns);
	else
		sh2000_sleep_real(ns);
}

static void ports_close(struct sh2000 *h)
{
	struct sh2000_ports *p = ports(h);

	if (p->close)
		p->close(p->ctx);
	memset(p, 0, sizeof(*p));
}

#define PORTS_BACKEND(k, vt) {				\
	.kind = (k),					\
	.virtual_time = (vt),				\
	.port_out = ports_out,				\
	.port_in = ports_in,				\
	.now_ns = ports_now,				\
	.wait_ns = ports_wait,				\
	.counters = sh2000_bus_counters,		\
	.close = ports_close,				\
}

/* [simulated][virtual time] */
static const struct sh2000_backend ports_backends[2][2] = {
	{ PORTS_BACKEND(SH2000_BACKEND_PORTS, 0),
	  PORTS_BACKEND(SH2000_BACKEND_PORTS, 1) },
	{ PORTS_BACKEND(SH2000_BACKEND_SIM, 0),
	  PORTS_BACKEND(SH2000_BACKEND_SIM, 1) },
};

int sh2000_ports_attach(struct sh2000 *h, const struct sh2000_ports *p,
			char *msg, size_t len)
{
	int vt;

	if (!p || p->size < sizeof(*p) || !p->out || !p->in) {
		if (p && p->close)
			p->close(p->ctx);
		return sh2000_msg(msg, len, -EINVAL,
				  "%s: struct sh2000_ports needs size, out and in",
				  h->device);
	}
	vt = !!(p->flags & SH2000_PORTS_F_VIRTUAL_TIME);
	if (vt && (!p->now_ns || !p->advance_ns)) {
		if (p->close)
			p->close(p->ctx);
		return sh2000_msg(msg, len, -EINVAL,
				  "%s: virtual time needs now_ns and advance_ns",
				  h->device);
	}
	h->priv = malloc(sizeof(*p));
	if (!h->priv) {
		if (p->close)
			p->close(p->ctx);
		return sh2000_msg(msg, len, -ENOMEM, "%s: out of memory",
				  h->device);
	}
	*ports(h) = *p;
	ports(h)->size = sizeof(*p);
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	h->be = &ports_backends[!!(p->flags & SH2000_PORTS_F_SIMULATED)][vt];
	return 0;
}

int sh2000_ports_call(struct sh2000 *h,
		      int (*fn)(const struct sh2000_ports *p, void *arg),
		      void *arg)
{
	int r;

	if (!h || !fn)
		return -EINVAL;
	if (h->be->port_out != ports_out)
		return sh2000_fail(h, -SH2000_ENOTSIM,
				   "%s: not a card opened on struct sh2000_ports",
				   h->device);
	pthread_mutex_lock(&h->lock);
	r = fn(ports(h), arg);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_watch_cycles(struct sh2000 *h, sh2000_cycle_fn fn, void *arg)
{
	int r;

	if (!h)
		return -EINVAL;
	if (h->be->port_out != ports_out || !ports(h)->watch)
		return sh2000_fail(h, -SH2000_ENOTSIM,
				   "%s: only a simulated card shows its servo cycles",
				   h->device);
	pthread_mutex_lock(&h->lock);
	r = ports(h)->watch(ports(h)->ctx, fn, arg);
	pthread_mutex_unlock(&h->lock);
	return r;
}
