/* SPDX-License-Identifier: MIT */
/*
 * sim: the card model in-process, in virtual time. Every port access costs
 * one port cycle of card time inside the model; waits advance the model
 * instead of sleeping.
 */
#include <errno.h>

#include "sh2000/sim.h"
#include "sh2000_internal.h"

static void sim_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	sh2000_cardsim_out(h->sim, reg, v);
}

static uint16_t sim_in(struct sh2000 *h, unsigned int reg)
{
	return sh2000_cardsim_in(h->sim, reg);
}

static uint64_t sim_now(struct sh2000 *h)
{
	return sh2000_cardsim_now_ns(h->sim);
}

static void sim_wait(struct sh2000 *h, uint64_t ns)
{
	sh2000_cardsim_advance(h->sim, ns);
}

static void sim_close(struct sh2000 *h)
{
	if (h->sim)
		sh2000_cardsim_destroy(h->sim);
	h->sim = NULL;
}

static const struct sh2000_backend sim_backend = {
	.kind = SH2000_BACKEND_SIM,
	.virtual_time = 1,
	.port_out = sim_out,
	.port_in = sim_in,
	.now_ns = sim_now,
	.wait_ns = sim_wait,
	.counters = sh2000_bus_counters,
	.close = sim_close,
};

int sh2000_simbe_open(struct sh2000 *h, const struct sh2000_sim_config *cfg,
		      char *msg, size_t len)
{
	struct sh2000_sim_config def;
	int r;

	if (!cfg) {
		sh2000_sim_config_default(&def);
		cfg = &def;
	}
	r = sh2000_cardsim_create(&h->sim, cfg);
	if (r < 0)
		return sh2000_msg(msg, len, r, "sim: cannot create the card model: %s",
				  sh2000_strerror(r));
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	h->be = &sim_backend;
	return 0;
}

struct sh2000_cardsim *sh2000_sim_card(struct sh2000 *h)
{
	return h && h->be && h->be->kind == SH2000_BACKEND_SIM ? h->sim : NULL;
}

int sh2000_sim_inject(struct sh2000 *h, enum sh2000_inject what,
		      unsigned int axis, unsigned int arg)
{
	int r;

	if (!sh2000_sim_card(h))
		return h ? sh2000_fail(h, -SH2000_ENOTSIM, "injection needs `sim`")
			 : -EINVAL;
	pthread_mutex_lock(&h->lock);
	r = sh2000_fw_inject(sh2000_cardsim_fw(h->sim), what, axis, arg);
	if (r < 0)
		sh2000_fail(h, r, "inject %d axis %u arg %u: %s", (int)what,
			    axis, arg, sh2000_strerror(r));
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_sim_probe(struct sh2000 *h, struct sh2000_probe *p)
{
	if (!sh2000_sim_card(h))
		return h ? sh2000_fail(h, -SH2000_ENOTSIM, "probe needs `sim`")
			 : -EINVAL;
	pthread_mutex_lock(&h->lock);
	sh2000_fw_probe(sh2000_cardsim_fw(h->sim), p);
	pthread_mutex_unlock(&h->lock);
	return 0;
}

int sh2000_sim_set_observer(struct sh2000 *h, sh2000_fw_observer fn,
			    void *ctx)
{
	if (!sh2000_sim_card(h))
		return h ? sh2000_fail(h, -SH2000_ENOTSIM, "observer needs `sim`")
			 : -EINVAL;
	pthread_mutex_lock(&h->lock);
	sh2000_fw_set_observer(sh2000_cardsim_fw(h->sim), fn, ctx);
	pthread_mutex_unlock(&h->lock);
	return 0;
}
