// SPDX-License-Identifier: MIT
/*
 * Data gathering (protocol 1.2, docs/protocol.md section 17), like PMAC's
 * "gather": the host chooses signals per axis, a period in servo cycles and
 * a trigger; the firmware records into its own memory at the end of the
 * servo interrupt, when every signal of the cycle is final, and answers
 * GATHER_READ with a chunk of the record in the window at the top of the
 * dual-port RAM, sealed by a check word.
 *
 * Memory: a pre-trigger ring of PRETRIGGER samples at the start of the
 * buffer, then the samples from the trigger on, in order. Nothing here
 * allocates; a sample costs one store per value.
 */
#include <math.h>

#include "cardmodel.h"

#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))

static uint32_t values_per_sample(const struct sh2000_gather_cfg *c)
{
	uint32_t n = 0;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		n += (uint32_t)__builtin_popcount(c->mask[a]);
	return n;
}

static int recording(const struct sh2000_gather *g)
{
	return g->state == SH2000_GATHER_ARMED ||
	       g->state == SH2000_GATHER_RECORDING;
}

static uint16_t set_field(struct sh2000_gather *g, uint16_t axis,
			  uint16_t field, uint32_t v)
{
	struct sh2000_gather_cfg *c = &g->cfg;

	if (field >= SH2000_GATHER_FIELDS)
		return SH2000_RES_BAD_PARAM;
	if (field == SH2000_GF_SIGNALS ? axis >= SH2000_AXES :
					 axis != SH2000_AXIS_GLOBAL)
		return SH2000_RES_BAD_AXIS;
	if (recording(g))
		return SH2000_RES_BUSY;
	switch (field) {
	case SH2000_GF_SIGNALS:
		if (v & ~((1u << SH2000_GATHER_SIGNALS) - 1u))
			return SH2000_RES_BAD_VALUE;
		c->mask[axis] = (uint16_t)v;
		return SH2000_RES_OK;
	case SH2000_GF_PERIOD:
		if (v < 1u || v > 0xffffu)
			return SH2000_RES_BAD_VALUE;
		c->period = v;
		return SH2000_RES_OK;
	case SH2000_GF_SAMPLES:
		if (v < 1u || v > SH2000_GATHER_BUFFER_VALUES)
			return SH2000_RES_BAD_VALUE;
		c->samples = v;
		return SH2000_RES_OK;
	case SH2000_GF_TRIGGER:
		if (v > SH2000_GATHER_ON_FAULT)
			return SH2000_RES_BAD_VALUE;
		c->trigger = (uint16_t)v;
		return SH2000_RES_OK;
	default:	/* SH2000_GF_PRETRIGGER */
		if (v >= SH2000_GATHER_BUFFER_VALUES)
			return SH2000_RES_BAD_VALUE;
		c->pretrigger = v;
		return SH2000_RES_OK;
	}
}

/* The configuration as a whole is checked when it is armed; the record
 * keeps its own copy, so the next one can be set up meanwhile. */
static uint16_t arm(struct sh2000_dsp *fw, uint32_t *value)
{
	struct sh2000_gather *g = &fw->gather;
	const struct sh2000_gather_cfg *c = &g->cfg;
	uint32_t vps = values_per_sample(c);

	if (recording(g))
		return SH2000_RES_BUSY;
	if (vps == 0 || (uint64_t)c->samples * vps > SH2000_GATHER_BUFFER_VALUES ||
	    c->pretrigger >= c->samples ||
	    (c->trigger == SH2000_GATHER_NOW && c->pretrigger))
		return SH2000_RES_BAD_VALUE;
	g->rec = *c;
	g->vps = vps;
	g->record++;
	g->pre_next = 0;
	g->pre_count = 0;
	g->post = 0;
	g->div = 0;
	g->trig_index = SH2000_GATHER_NO_TRIGGER;
	g->trig_cycle = 0;
	g->first_cycle = 0;
	g->last_cycle = 0;
	g->prev_faults = fw->faults;
	g->was_moving = sh2000_fw_in_motion(fw);
	g->state = SH2000_GATHER_ARMED;
	if (c->trigger == SH2000_GATHER_NOW) {
		g->state = SH2000_GATHER_RECORDING;
		g->trig_cycle = (uint32_t)fw->cycle;
	}
	*value = g->record;
	return SH2000_RES_OK;
}

static void stop(struct sh2000_gather *g)
{
	if (!recording(g))
		return;
	g->state = SH2000_GATHER_DONE;
	if (g->pre_count + g->post)
		g->first_cycle = g->last_cycle -
				 (g->pre_count + g->post - 1u) * g->rec.period;
}

static uint32_t f32(double v)
{
	return sh2000_f32_bits(v);
}

/* One axis' signal this cycle, as 32 bits. */
static uint32_t signal(const struct sh2000_dsp *fw, unsigned int a,
		       unsigned int sig)
{
	const struct sh2000_fw_axis *ax = &fw->ax[a];

	switch (sig) {
	case SH2000_GS_SETPOINT:
		return (uint32_t)sh2000_fw_cmd_counts(ax);
	case SH2000_GS_ENCODER:
		return (uint32_t)(uint64_t)ax->act;
	case SH2000_GS_FERR:
		return f32(sh2000_fw_ferr(fw, a));
	case SH2000_GS_DAC:
		return (uint32_t)(int32_t)ax->dac;
	case SH2000_GS_PID_P:
		return f32(ax->pid.p);
	case SH2000_GS_PID_I:
		return f32(ax->pid.i);
	case SH2000_GS_PID_D:
		return f32(ax->pid.d);
	case SH2000_GS_FF:
		return f32(ax->pid.ff);
	case SH2000_GS_VELOCITY:
		return f32((double)ax->delta / sh2000_fw_servo_s(fw));
	default:	/* SH2000_GS_SETPOINT_VEL */
		return f32(ax->cmd_v);
	}
}

static void store(struct sh2000_dsp *fw, uint32_t slot)
{
	struct sh2000_gather *g = &fw->gather;
	uint32_t *out = &g->buf[slot * g->vps];
	unsigned int a, s;

	for (a = 0; a < SH2000_AXES; a++)
		for (s = 0; s < SH2000_GATHER_SIGNALS; s++)
			if (g->rec.mask[a] & (1u << s))
				*out++ = signal(fw, a, s);
	g->last_cycle = (uint32_t)fw->cycle;
}

static int triggered(struct sh2000_dsp *fw)
{
	struct sh2000_gather *g = &fw->gather;
	int moving = sh2000_fw_in_motion(fw), fired = 0;

	if (g->state == SH2000_GATHER_ARMED) {
		if (g->rec.trigger == SH2000_GATHER_ON_MOTION)
			fired = moving && !g->was_moving;
		else if (g->rec.trigger == SH2000_GATHER_ON_FAULT)
			fired = (fw->faults & ~g->prev_faults) != 0;
	}
	g->was_moving = moving;
	g->prev_faults = fw->faults;
	return fired;
}

/*
 * End of the servo interrupt. Samples fall every PERIOD cycles: from the
 * arming cycle while waiting with a pre-trigger (so the trigger sample is
 * the first one at or after the trigger, spaced like the others), from the
 * trigger cycle itself without one.
 */
void sh2000_gather_cycle(struct sh2000_dsp *fw)
{
	struct sh2000_gather *g = &fw->gather;
	const struct sh2000_gather_cfg *r = &g->rec;

	if (triggered(fw)) {
		g->state = SH2000_GATHER_RECORDING;
		g->trig_cycle = (uint32_t)fw->cycle;
		if (r->pretrigger == 0)
			g->div = 0;
	}
	if (!recording(g) ||
	    (g->state == SH2000_GATHER_ARMED && r->pretrigger == 0))
		return;
	if (g->div) {
		g->div--;
		return;
	}
	g->div = r->period - 1u;
	if (g->state == SH2000_GATHER_ARMED) {
		store(fw, g->pre_next);
		g->pre_next = (g->pre_next + 1u) % r->pretrigger;
		if (g->pre_count < r->pretrigger)
			g->pre_count++;
		return;
	}
	if (g->post == 0) {
		g->trig_index = g->pre_count;
		g->first_cycle = (uint32_t)fw->cycle - g->pre_count * r->period;
	}
	store(fw, r->pretrigger + g->post);
	if (++g->post >= r->samples - r->pretrigger)
		g->state = SH2000_GATHER_DONE;
}

/* Value v of the record (0 = the oldest sample's first value). */
static uint32_t record_value(const struct sh2000_gather *g, uint32_t v)
{
	uint32_t s = v / g->vps, k = v % g->vps, slot;

	if (s < g->pre_count)
		slot = (g->pre_next + g->rec.pretrigger - g->pre_count + s) %
		       g->rec.pretrigger;
	else
		slot = g->rec.pretrigger + (s - g->pre_count);
	return g->buf[slot * g->vps + k];
}

static void put32(uint16_t *w, uint32_t v)
{
	w[0] = (uint16_t)(v & 0xffffu);
	w[1] = (uint16_t)(v >> 16);
}

/* Header, check word, then the words into the RAM (before CMD_ACK). */
static void publish(struct sh2000_dsp *fw, uint16_t *w, uint16_t seq,
		    uint16_t kind, unsigned int count, uint32_t offset)
{
	const struct sh2000_gather *g = &fw->gather;
	unsigned int i;

	w[SH2000_GW_SEQ] = seq;
	w[SH2000_GW_KIND] = kind;
	w[SH2000_GW_RECORD] = g->record;
	w[SH2000_GW_COUNT] = (uint16_t)count;
	put32(&w[SH2000_GW_OFFSET_LO], offset);
	w[SH2000_GW_STATE] = g->state;
	w[SH2000_GW_CHECK] = sh2000_gather_check(w, count);
	for (i = 0; i < SH2000_GW_HEADER + count; i++)
		WR(fw, SH2000_W_GATHER_BASE + i, w[i]);
}

static uint16_t info(struct sh2000_dsp *fw, uint16_t seq, uint32_t *value)
{
	const struct sh2000_gather *g = &fw->gather;
	/* the record's layout once there is one, else what would be armed */
	const struct sh2000_gather_cfg *c = g->state ? &g->rec : &g->cfg;
	uint16_t w[SH2000_GATHER_WINDOW_WORDS] = { 0 };
	uint16_t *p = &w[SH2000_GW_HEADER];
	unsigned int a;

	p[SH2000_GI_TRIGGER] = c->trigger;
	p[SH2000_GI_PERIOD] = (uint16_t)c->period;
	p[SH2000_GI_VALUES] = (uint16_t)values_per_sample(c);
	for (a = 0; a < SH2000_AXES; a++)
		p[SH2000_GI_SIGNALS(a)] = c->mask[a];
	put32(&p[SH2000_GI_SAMPLES_LO], g->pre_count + g->post);
	put32(&p[SH2000_GI_CAPACITY_LO], c->samples);
	put32(&p[SH2000_GI_PRETRIGGER_LO], c->pretrigger);
	put32(&p[SH2000_GI_TRIGGER_INDEX_LO], g->trig_index);
	put32(&p[SH2000_GI_FIRST_CYCLE_LO], g->first_cycle);
	put32(&p[SH2000_GI_TRIGGER_CYCLE_LO], g->trig_cycle);
	put32(&p[SH2000_GI_BUFFER_LO], SH2000_GATHER_BUFFER_VALUES);
	publish(fw, w, seq, SH2000_GATHER_KIND_INFO, SH2000_GATHER_INFO_WORDS, 0);
	*value = g->state;
	return SH2000_RES_OK;
}

static uint16_t read_chunk(struct sh2000_dsp *fw, uint16_t seq, uint32_t first,
			   uint32_t *value)
{
	const struct sh2000_gather *g = &fw->gather;
	uint16_t w[SH2000_GATHER_WINDOW_WORDS];
	uint32_t total = (g->pre_count + g->post) * g->vps, n, i;

	if (g->state != SH2000_GATHER_DONE)
		return SH2000_RES_BUSY;
	if (first >= total)
		return SH2000_RES_BAD_VALUE;
	n = total - first < SH2000_GATHER_CHUNK_VALUES ?
		    total - first : SH2000_GATHER_CHUNK_VALUES;
	for (i = 0; i < n; i++)
		put32(&w[SH2000_GW_HEADER + 2u * i], record_value(g, first + i));
	publish(fw, w, seq, SH2000_GATHER_KIND_DATA, 2u * n, first);
	*value = n;
	return SH2000_RES_OK;
}

uint16_t sh2000_gather_command(struct sh2000_dsp *fw, uint16_t seq,
			       uint16_t op, uint16_t axis, uint16_t param,
			       uint32_t arg, uint32_t *value)
{
	switch (op) {
	case SH2000_CMD_GATHER_SET:
		return set_field(&fw->gather, axis, param, arg);
	case SH2000_CMD_GATHER_ARM:
		return arm(fw, value);
	case SH2000_CMD_GATHER_STOP:
		stop(&fw->gather);
		return SH2000_RES_OK;
	case SH2000_CMD_GATHER_INFO:
		return info(fw, seq, value);
	case SH2000_CMD_GATHER_READ:
		return read_chunk(fw, seq, arg, value);
	default:
		return SH2000_RES_BAD_OP;
	}
}

void sh2000_gather_boot(struct sh2000_gather *g)
{
	g->state = SH2000_GATHER_OFF;
	g->cfg.period = 1;
	g->cfg.samples = 1000;
	g->cfg.trigger = SH2000_GATHER_NOW;
	g->cfg.pretrigger = 0;
	g->rec = g->cfg;
}
