// SPDX-License-Identifier: MIT
/*
 * `sim`: a whole card model in the caller's process, in virtual time,
 * behind the four registers of struct sh2000_ports. Every port access costs
 * one port cycle of card time inside the model; waits advance the model
 * instead of sleeping. libsh2000 opens it through the provider below when
 * a program asks for "sim"; sh2000_sim_open() does the same with a plant
 * configuration. The sh2000_sim_*() calls on a handle reach the model
 * through sh2000_ports_call(), under the handle's lock.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "sh2000/sim.h"
#include "sh2000_simprovider.h"
#include "simutil.h"

struct simport {
	struct sh2000_cardsim *card;
	sh2000_cycle_fn watch_fn;	/* sh2000_watch_cycles() */
	void *watch_arg;
	sh2000_fw_observer obs_fn;	/* sh2000_sim_set_observer() */
	void *obs_arg;
};

static void sp_out(void *ctx, unsigned int reg, uint16_t v)
{
	sh2000_cardsim_out(((struct simport *)ctx)->card, reg, v);
}

static uint16_t sp_in(void *ctx, unsigned int reg)
{
	return sh2000_cardsim_in(((struct simport *)ctx)->card, reg);
}

static uint64_t sp_now(void *ctx)
{
	return sh2000_cardsim_now_ns(((struct simport *)ctx)->card);
}

static void sp_advance(void *ctx, uint64_t ns)
{
	sh2000_cardsim_advance(((struct simport *)ctx)->card, ns);
}

static void sp_close(void *ctx)
{
	struct simport *sp = ctx;

	sh2000_cardsim_destroy(sp->card);
	free(sp);
}

/* The firmware has one observer slot; both users share it. */
static void sp_observe(void *ctx, const struct sh2000_probe *p)
{
	struct simport *sp = ctx;

	if (sp->watch_fn) {
		struct sh2000_cycle c;
		unsigned int a;

		c.servo_cycle = p->servo_cycle;
		c.time_ns = p->time_ns;
		c.state = p->state;
		for (a = 0; a < SH2000_AXES; a++) {
			c.axis[a].fine_cmd = p->axis[a].fine_cmd;
			c.axis[a].actual = p->axis[a].actual;
			c.axis[a].velocity = p->axis[a].velocity;
			c.axis[a].dac = p->axis[a].dac;
		}
		sp->watch_fn(sp->watch_arg, &c);
	}
	if (sp->obs_fn)
		sp->obs_fn(sp->obs_arg, p);
}

static void sp_observers_changed(struct simport *sp)
{
	sh2000_fw_set_observer(sh2000_cardsim_fw(sp->card),
			       sp->watch_fn || sp->obs_fn ? sp_observe : NULL,
			       sp);
}

static int sp_watch(void *ctx, sh2000_cycle_fn fn, void *arg)
{
	struct simport *sp = ctx;

	sp->watch_fn = fn;
	sp->watch_arg = arg;
	sp_observers_changed(sp);
	return 0;
}

static int sp_new(struct sh2000_ports *p, const struct sh2000_sim_config *cfg,
		  char *msg, size_t len)
{
	struct sh2000_sim_config def;
	struct simport *sp;
	int r;

	if (!cfg) {
		sh2000_sim_config_default(&def);
		cfg = &def;
	}
	sp = calloc(1, sizeof(*sp));
	if (!sp)
		return sim_msg(msg, len, -ENOMEM, "sim: out of memory");
	r = sh2000_cardsim_create(&sp->card, cfg);
	if (r < 0) {
		free(sp);
		return sim_msg(msg, len, r, "sim: cannot create the card model: %s",
			       sh2000_strerror(r));
	}
	memset(p, 0, sizeof(*p));
	p->size = sizeof(*p);
	p->flags = SH2000_PORTS_F_VIRTUAL_TIME | SH2000_PORTS_F_SIMULATED;
	p->ctx = sp;
	p->out = sp_out;
	p->in = sp_in;
	p->now_ns = sp_now;
	p->advance_ns = sp_advance;
	p->watch = sp_watch;
	p->close = sp_close;
	return 0;
}

int sh2000_sim_open(struct sh2000 **out, const struct sh2000_sim_config *cfg,
		    char *msg, size_t msglen)
{
	struct sh2000_ports p;
	int r;

	if (!out)
		return -EINVAL;
	*out = NULL;
	r = sp_new(&p, cfg, msg, msglen);
	if (r < 0)
		return r;
	return sh2000_open_ports(out, &p, "sim", msg, msglen);
}

static int open_default(struct sh2000_ports *p, char *msg, size_t len)
{
	return sp_new(p, NULL, msg, len);
}

/* What libsh2000 looks up when a program opens "sim". */
const struct sh2000_sim_provider sh2000_sim_provider_v1 = {
	.abi = SH2000_SIM_PROVIDER_ABI,
	.open_ports = open_default,
};

/* ---- reaching the model inside a handle ---- */

struct sp_call {
	int (*fn)(struct simport *sp, struct sp_call *c);
	enum sh2000_inject what;
	unsigned int axis, arg;
	struct sh2000_probe *probe;
	sh2000_fw_observer obs;
	void *obs_arg;
	struct sh2000_cardsim *card;
	double ppm;
	double *tool;
	const struct sh2000_geometry *geom;
};

static int sp_dispatch(const struct sh2000_ports *p, void *arg)
{
	struct sp_call *c = arg;

	/* only our own ports carry a struct simport */
	if (p->out != sp_out)
		return -SH2000_ENOTSIM;
	return c->fn(p->ctx, c);
}

static int call(struct sh2000 *h, struct sp_call *c)
{
	if (!h)
		return -EINVAL;
	return sh2000_ports_call(h, sp_dispatch, c);
}

static int do_card(struct simport *sp, struct sp_call *c)
{
	c->card = sp->card;
	return 0;
}

struct sh2000_cardsim *sh2000_sim_card(struct sh2000 *h)
{
	struct sp_call c = { .fn = do_card };

	if (!h || sh2000_backend(h) != SH2000_BACKEND_SIM)
		return NULL;
	return call(h, &c) < 0 ? NULL : c.card;
}

static int do_inject(struct simport *sp, struct sp_call *c)
{
	return sh2000_fw_inject(sh2000_cardsim_fw(sp->card), c->what, c->axis,
				c->arg);
}

int sh2000_sim_inject(struct sh2000 *h, enum sh2000_inject what,
		      unsigned int axis, unsigned int arg)
{
	struct sp_call c = { .fn = do_inject, .what = what, .axis = axis,
			     .arg = arg };

	return call(h, &c);
}

static int do_probe(struct simport *sp, struct sp_call *c)
{
	sh2000_fw_probe(sh2000_cardsim_fw(sp->card), c->probe);
	return 0;
}

int sh2000_sim_probe(struct sh2000 *h, struct sh2000_probe *p)
{
	struct sp_call c = { .fn = do_probe, .probe = p };

	return call(h, &c);
}

static int do_tool(struct simport *sp, struct sp_call *c)
{
	sh2000_fw_tool_position(sh2000_cardsim_fw(sp->card), c->tool);
	return 0;
}

int sh2000_sim_tool_position(struct sh2000 *h, double tool_mm[SH2000_AXES])
{
	struct sp_call c = { .fn = do_tool, .tool = tool_mm };

	return call(h, &c);
}

static int do_geometry(struct simport *sp, struct sp_call *c)
{
	return sh2000_fw_set_geometry(sh2000_cardsim_fw(sp->card), c->geom);
}

int sh2000_sim_set_geometry(struct sh2000 *h, const struct sh2000_geometry *g)
{
	struct sp_call c = { .fn = do_geometry, .geom = g };

	return call(h, &c);
}

static int do_observer(struct simport *sp, struct sp_call *c)
{
	sp->obs_fn = c->obs;
	sp->obs_arg = c->obs_arg;
	sp_observers_changed(sp);
	return 0;
}

int sh2000_sim_set_observer(struct sh2000 *h, sh2000_fw_observer fn,
			    void *ctx)
{
	struct sp_call c = { .fn = do_observer, .obs = fn, .obs_arg = ctx };

	return call(h, &c);
}

static int do_clock(struct simport *sp, struct sp_call *c)
{
	return sh2000_fw_set_clock_ppm(sh2000_cardsim_fw(sp->card), c->ppm) < 0 ?
		       -EINVAL : 0;
}

int sh2000_sim_set_clock_ppm(struct sh2000 *h, double ppm)
{
	struct sp_call c = { .fn = do_clock, .ppm = ppm };

	return call(h, &c);
}

const char *sh2000_sim_version(void)
{
	return SH2000_SIM_VERSION;
}
