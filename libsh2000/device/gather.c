/* SPDX-License-Identifier: MIT */
/*
 * Data gathering (protocol 1.2, docs/protocol.md section 17): configure and
 * arm a record on the card, wait for it, read it out. Each chunk is one
 * hold of the command slot (command, answer, the window read before the
 * slot is given up): about 1.3 ms of port time, so other programs'
 * commands go on between chunks however long the record. A chunk is
 * accepted only when its check word, sequence number, record number,
 * offset and count are the ones asked for.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "sh2000_internal.h"

/* Re-reads of a chunk whose check word is wrong before giving up. */
#define GATHER_TRIES	3
/* How often sh2000_gather_wait() asks the card. */
#define GATHER_POLL_NS	2000000ull

void sh2000_gather_config_default(struct sh2000_gather_config *c)
{
	memset(c, 0, sizeof(*c));
	c->period = 1;
	c->samples = 1000;
	c->trigger = SH2000_GATHER_NOW;
}

static int need_gather(struct sh2000 *h)
{
	return sh2000_need_minor(h, SH2000_PROTO_MINOR_GATHER, "data gathering needs");
}

static unsigned int values_of(const unsigned int signals[SH2000_AXES])
{
	unsigned int a, n = 0;

	for (a = 0; a < SH2000_AXES; a++)
		n += (unsigned int)__builtin_popcount(signals[a]);
	return n;
}

/* The card's rules, before anything is sent. */
static int check_config(struct sh2000 *h, const struct sh2000_gather_config *c)
{
	unsigned int a, n = values_of(c->signals);

	for (a = 0; a < SH2000_AXES; a++)
		if (c->signals[a] & ~((1u << SH2000_GATHER_SIGNALS) - 1u))
			return sh2000_fail(h, -SH2000_EPARAM,
					   "gather: axis %u signals 0x%x: only bits 0..%u are signals",
					   a, c->signals[a], SH2000_GATHER_SIGNALS - 1);
	if (!n)
		return sh2000_fail(h, -SH2000_EPARAM, "gather: no signal chosen");
	if (c->period < 1 || c->period > 65535)
		return sh2000_fail(h, -SH2000_EPARAM,
				   "gather: period %u: must be 1..65535 servo cycles",
				   c->period);
	if (c->samples < 1 || (uint64_t)c->samples * n > SH2000_GATHER_BUFFER_VALUES)
		return sh2000_fail(h, -SH2000_EPARAM,
				   "gather: %u samples of %u values: the card holds 1..%u values",
				   c->samples, n, SH2000_GATHER_BUFFER_VALUES);
	if (c->trigger > SH2000_GATHER_ON_FAULT)
		return sh2000_fail(h, -SH2000_EPARAM,
				   "gather: trigger %u: must be 0 (now), 1 (motion) or 2 (fault)",
				   c->trigger);
	if (c->pretrigger >= c->samples ||
	    (c->pretrigger && c->trigger == SH2000_GATHER_NOW))
		return sh2000_fail(h, -SH2000_EPARAM,
				   "gather: pre-trigger %u: must be below the %u samples, and 0 with trigger now",
				   c->pretrigger, c->samples);
	return 0;
}

/* One GATHER_SET per field, axes' signal masks first, in the order of
 * protocol.md §17; the first refusal ends it (nothing is armed). */
static int configure_fields(struct sh2000 *h,
			    const struct sh2000_gather_config *c)
{
	const struct {
		uint16_t field;
		uint32_t value;
	} global[] = {
		{ SH2000_GF_PERIOD, c->period },
		{ SH2000_GF_SAMPLES, c->samples },
		{ SH2000_GF_TRIGGER, c->trigger },
		{ SH2000_GF_PRETRIGGER, c->pretrigger },
	};
	unsigned int a, k;
	int r = 0;

	for (a = 0; !r && a < SH2000_AXES; a++)
		r = sh2000_cmd_exchange(h, SH2000_CMD_GATHER_SET, a,
					SH2000_GF_SIGNALS, (int32_t)c->signals[a],
					NULL, SH2000_CMD_TIMEOUT_MS);
	for (k = 0; !r && k < sizeof(global) / sizeof(global[0]); k++)
		r = sh2000_cmd_exchange(h, SH2000_CMD_GATHER_SET, SH2000_AXIS_GLOBAL,
					global[k].field, (int32_t)global[k].value,
					NULL, SH2000_CMD_TIMEOUT_MS);
	return r;
}

static int configure_and_arm(struct sh2000 *h,
			     const struct sh2000_gather_config *c)
{
	int32_t record = 0;
	int r = configure_fields(h, c);

	if (!r)
		r = sh2000_cmd_exchange(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, &record,
					SH2000_CMD_TIMEOUT_MS);
	if (r == -SH2000_ECMD_BUSY)
		r = sh2000_fail(h, r, "gather: a record is armed or recording (stop the gathering first)");
	return r < 0 ? r : (int)(record & 0xffff);
}

int sh2000_gather_start(struct sh2000 *h, const struct sh2000_gather_config *c)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = need_gather(h);
	if (!r)
		r = check_config(h, c);
	/* one hold of the slot: another program's settings cannot slip in
	 * between these and the arming */
	if (!r)
		r = sh2000_cmd_slot_take(h, "gather start");
	if (!r) {
		r = configure_and_arm(h, c);
		sh2000_cmd_slot_drop(h);
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_gather_stop(struct sh2000 *h)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = need_gather(h);
	if (!r)
		r = sh2000_command_locked(h, SH2000_CMD_GATHER_STOP, 0, 0, 0, NULL,
					  SH2000_CMD_TIMEOUT_MS);
	pthread_mutex_unlock(&h->lock);
	return r;
}

/*
 * One exchange whose answer is in the window: command, then the window's
 * first `words` words, both inside one hold of the slot. 0, or an error.
 */
static int window_exchange(struct sh2000 *h, unsigned int op, uint32_t arg,
			   uint16_t *w, unsigned int words, int32_t *value)
{
	int r = sh2000_cmd_slot_take(h, "gather");

	if (r < 0)
		return r;
	r = sh2000_cmd_exchange(h, op, 0, 0, (int32_t)arg, value,
				SH2000_CMD_TIMEOUT_MS);
	if (!r)
		r = sh2000_rd(h, SH2000_W_GATHER_BASE, words, w);
	if (!r && w[SH2000_GW_SEQ] != h->cmd.seq)
		r = 1;	/* not our answer: only a broken card does that */
	sh2000_cmd_slot_drop(h);
	return r;
}

static int window_ok(const uint16_t *w, uint16_t kind, unsigned int count)
{
	return w[SH2000_GW_KIND] == kind && w[SH2000_GW_COUNT] == count &&
	       w[SH2000_GW_CHECK] == sh2000_gather_check(w, count);
}

static uint32_t w32(const uint16_t *w)
{
	return (uint32_t)w[0] | ((uint32_t)w[1] << 16);
}

static void decode_info(struct sh2000 *h, const uint16_t *w,
			struct sh2000_gather_info *gi)
{
	const uint16_t *p = &w[SH2000_GW_HEADER];
	unsigned int a;

	memset(gi, 0, sizeof(*gi));
	gi->state = w[SH2000_GW_STATE];
	gi->record = w[SH2000_GW_RECORD];
	gi->trigger = p[SH2000_GI_TRIGGER];
	gi->period = p[SH2000_GI_PERIOD];
	gi->values = p[SH2000_GI_VALUES];
	for (a = 0; a < SH2000_AXES; a++)
		gi->signals[a] = p[SH2000_GI_SIGNALS(a)];
	gi->samples = w32(&p[SH2000_GI_SAMPLES_LO]);
	gi->capacity = w32(&p[SH2000_GI_CAPACITY_LO]);
	gi->pretrigger = w32(&p[SH2000_GI_PRETRIGGER_LO]);
	gi->trigger_index = w32(&p[SH2000_GI_TRIGGER_INDEX_LO]);
	gi->first_cycle = w32(&p[SH2000_GI_FIRST_CYCLE_LO]);
	gi->trigger_cycle = w32(&p[SH2000_GI_TRIGGER_CYCLE_LO]);
	gi->buffer = w32(&p[SH2000_GI_BUFFER_LO]);
	gi->sample_s = (double)gi->period * (double)h->servo_ns * 1e-9;
}

static int info_locked(struct sh2000 *h, struct sh2000_gather_info *gi)
{
	uint16_t w[SH2000_GW_HEADER + SH2000_GATHER_INFO_WORDS];
	int tries, r = 0;

	for (tries = 0; tries < GATHER_TRIES; tries++) {
		r = window_exchange(h, SH2000_CMD_GATHER_INFO, 0, w,
				    SH2000_GW_HEADER + SH2000_GATHER_INFO_WORDS,
				    NULL);
		if (r < 0)
			return r;
		if (!r && window_ok(w, SH2000_GATHER_KIND_INFO,
				    SH2000_GATHER_INFO_WORDS)) {
			decode_info(h, w, gi);
			if (gi->values == values_of(gi->signals))
				return 0;
		}
	}
	return sh2000_fail(h, -SH2000_EGATHER_CHECK,
			   "gather info: the window failed its check %d times",
			   GATHER_TRIES);
}

int sh2000_gather_info(struct sh2000 *h, struct sh2000_gather_info *gi)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = need_gather(h);
	if (!r)
		r = info_locked(h, gi);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_gather_wait(struct sh2000 *h, unsigned int record,
		       struct sh2000_gather_info *gi, int timeout_ms)
{
	uint64_t t0 = sh2000_now_ns(h);
	int32_t state = 0;
	int r;

	pthread_mutex_lock(&h->lock);
	r = need_gather(h);
	pthread_mutex_unlock(&h->lock);
	if (r < 0)
		return r;
	for (;;) {
		/* INFO's value is the state: the window is read only once */
		r = sh2000_command(h, SH2000_CMD_GATHER_INFO, 0, 0, 0, &state);
		if (r < 0)
			return r;
		if (state == SH2000_GATHER_DONE || state == SH2000_GATHER_OFF)
			break;
		if (timeout_ms >= 0 &&
		    sh2000_now_ns(h) - t0 > (uint64_t)timeout_ms * 1000000ull)
			return sh2000_fail(h, -SH2000_ETIMEOUT,
					   "gather: record %u not complete within %d ms",
					   record, timeout_ms);
		r = sh2000_poll(h, NULL);
		if (r < 0)
			return r;
		sh2000_sleep_ns(h, GATHER_POLL_NS);
	}
	r = sh2000_gather_info(h, gi);
	if (r == 0 && (gi->record != record || gi->state != SH2000_GATHER_DONE))
		r = sh2000_fail(h, -SH2000_EGATHER_LOST,
				"gather: record %u was replaced by record %u",
				record, gi->record);
	return r;
}

int sh2000_gather_column(const struct sh2000_gather_info *gi, unsigned int k,
			 unsigned int *axis, unsigned int *signal)
{
	unsigned int a, s;

	for (a = 0; a < SH2000_AXES; a++)
		for (s = 0; s < SH2000_GATHER_SIGNALS; s++) {
			if (!(gi->signals[a] & (1u << s)))
				continue;
			if (k-- == 0) {
				*axis = a;
				*signal = s;
				return 0;
			}
		}
	return -EINVAL;
}

static double value_of(const struct sh2000_gather_info *gi, uint32_t v,
		       uint32_t bits)
{
	unsigned int axis, sig;

	if (sh2000_gather_column(gi, v % gi->values, &axis, &sig) == 0 &&
	    sh2000_gather_signal_lookup(sig)->type == SH2000_PT_F32)
		return sh2000_f32_value(bits);
	return (double)(int32_t)bits;
}

/*
 * Values [first, first + n) (n <= one chunk) of the record into out. The
 * card always sends a whole chunk (60 values, fewer at the record's end)
 * and its check word covers all of it, so all of it is read even when
 * fewer values are wanted.
 */
static int read_chunk(struct sh2000 *h, const struct sh2000_gather_info *gi,
		      uint32_t first, unsigned int n, double *out)
{
	uint16_t w[SH2000_GATHER_WINDOW_WORDS];
	uint64_t total = (uint64_t)gi->samples * gi->values;
	unsigned int i, tries, sent;
	int r;

	sent = total - first < SH2000_GATHER_CHUNK_VALUES ?
		       (unsigned int)(total - first) : SH2000_GATHER_CHUNK_VALUES;
	for (tries = 0; tries < GATHER_TRIES; tries++) {
		pthread_mutex_lock(&h->lock);
		r = window_exchange(h, SH2000_CMD_GATHER_READ, first, w,
				    SH2000_GW_HEADER + 2u * sent, NULL);
		pthread_mutex_unlock(&h->lock);
		if (r < 0)
			return r;
		if (r || !window_ok(w, SH2000_GATHER_KIND_DATA, 2u * sent) ||
		    w32(&w[SH2000_GW_OFFSET_LO]) != first)
			continue;
		if (w[SH2000_GW_RECORD] != (gi->record & 0xffffu))
			return sh2000_fail(h, -SH2000_EGATHER_LOST,
					   "gather: record %u was replaced by record %u while it was read",
					   gi->record, w[SH2000_GW_RECORD]);
		for (i = 0; i < n; i++)
			out[i] = value_of(gi, first + i,
					  w32(&w[SH2000_GW_HEADER + 2u * i]));
		return 0;
	}
	return sh2000_fail(h, -SH2000_EGATHER_CHECK,
			   "gather: values %u..%u failed their check word %u times",
			   first, first + n - 1, GATHER_TRIES);
}

int sh2000_gather_read(struct sh2000 *h, const struct sh2000_gather_info *gi,
		       uint32_t first, uint32_t n, double *out)
{
	uint64_t v = (uint64_t)first * gi->values, end;
	int r;

	if (!gi->values || (uint64_t)first + n > gi->samples || n > INT32_MAX)
		return sh2000_fail(h, -EINVAL,
				   "gather: samples %u..%llu of a record of %u",
				   first, (unsigned long long)first + n, gi->samples);
	pthread_mutex_lock(&h->lock);
	r = need_gather(h);
	pthread_mutex_unlock(&h->lock);
	end = v + (uint64_t)n * gi->values;
	for (; !r && v < end; v += SH2000_GATHER_CHUNK_VALUES) {
		unsigned int k = end - v < SH2000_GATHER_CHUNK_VALUES ?
					 (unsigned int)(end - v) :
					 SH2000_GATHER_CHUNK_VALUES;

		r = read_chunk(h, gi, (uint32_t)v, k,
			       out + (v - (uint64_t)first * gi->values));
	}
	return r < 0 ? r : (int)n;
}
