// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000: SH-2000TH cards as LinuxCNC joints (LinuxCNC 2.9 uspace).
 *
 *   loadrt hal_sh2000 device=/dev/sh2000-0[,sim:NAME,...] [comp=FILE[,FILE...]]
 *
 * One instance sh2000.N per device string (up to 4), with the functions
 * sh2000.N.read (first in the servo thread) and sh2000.N.write (last).
 * The card fine-interpolates and closes the loops itself, so LinuxCNC
 * drives it like a position-mode drive (hostmot2's stepgen in position
 * mode, EtherCAT CSP through lcec). This file is only the HAL side: pins
 * in and out of hsc.h's structs; the behaviour is card.c, write.c and
 * timebase.c. Pins: hal_sh2000(9), docs/linuxcnc.md.
 *
 * Copyright (C) 2026 the SH-2000 authors. GPL-2.0-or-later because it
 * includes LinuxCNC's headers.
 */
#include <string.h>

#include "rtapi.h"
#include "rtapi_app.h"
#include "rtapi_string.h"
#include "hal.h"

#include "hsc.h"

MODULE_AUTHOR("SH-2000 project");
MODULE_DESCRIPTION("SH-2000TH ISA motion card (libsh2000) as LinuxCNC joints");
MODULE_LICENSE("GPL");

#define MAX_CARDS	4

static char *device[MAX_CARDS];
RTAPI_MP_ARRAY_STRING(device, MAX_CARDS,
		      "cards: /dev/sh2000-N, io:0xNNN or sim:NAME, comma-separated");

/* a compensation table file per card, loaded before the card runs */
static char *comp[MAX_CARDS];
RTAPI_MP_ARRAY_STRING(comp, MAX_CARDS,
		      "compensation table file per card (docs/compensation.md), comma-separated; - for none");

struct pins_axis {
	hal_float_t *position_cmd, *position_fb, *f_error, *encoder_position;
	hal_s32_t *counts;
	hal_bit_t *enable, *amp_fault, *home_sw, *limit_pos, *limit_neg;
	hal_bit_t *index_enable;
	hal_float_t position_scale;
	hal_bit_t index_mask, index_mask_invert, index_invert;
	hal_float_t index_within;
};

struct pins_card {
	hal_bit_t *ok, *estop, *fault, *fault_reset;
	hal_s32_t *queue_fill, *card_state, *pll_correction_ns;
	hal_float_t *delay_ms;
	hal_u32_t *underruns, *port_cycles;
	hal_s32_t queue_target;
	/* the card's active tables: identity, checksum, how many (loaded at
	 * start or later by another program: hal/comp.c's watch) */
	hal_u32_t comp_id, comp_sum, comp_tables;
	struct pins_axis axis[SH2000_AXES];
};

struct instance {
	struct pins_card *p;
	struct hsc_card card;
	struct hsc_in in;
	struct hsc_out out;
	char printed[sizeof(((struct hsc_card *)0)->err)];
};

static int comp_id;
static int ncards;
static struct instance inst[MAX_CARDS];

static void pins_in(struct instance *t)
{
	struct pins_card *p = t->p;
	unsigned int a;

	t->in.estop = *p->estop;
	t->in.fault_reset = *p->fault_reset;
	t->in.queue_target = p->queue_target;
	for (a = 0; a < SH2000_AXES; a++) {
		struct pins_axis *x = &p->axis[a];

		t->in.axis[a].position_cmd = *x->position_cmd;
		t->in.axis[a].enable = *x->enable;
		t->in.axis[a].index_enable = *x->index_enable;
		t->in.axis[a].index_mask = x->index_mask;
		t->in.axis[a].index_mask_invert = x->index_mask_invert;
		t->in.axis[a].index_invert = x->index_invert;
		t->in.axis[a].index_within = x->index_within;
		t->in.axis[a].position_scale = x->position_scale;
	}
	/* from the index mark on, commands are from it too (index.c) */
	hsc_index_command(&t->card, &t->in);
}

static void pins_out(struct instance *t, int read_half)
{
	struct pins_card *p = t->p;
	unsigned int a;

	*p->ok = t->out.ok;
	*p->fault = t->out.fault;
	*p->queue_fill = t->out.queue_fill;
	*p->card_state = t->out.card_state;
	*p->underruns = t->out.underruns;
	*p->port_cycles = t->out.port_cycles;
	*p->pll_correction_ns = t->out.pll_correction_ns;
	*p->delay_ms = t->out.delay_ms;
	for (a = 0; a < SH2000_AXES; a++) {
		struct pins_axis *x = &p->axis[a];
		const struct hsc_axis_out *o = &t->out.axis[a];

		*x->position_fb = o->position_fb;
		*x->encoder_position = o->encoder_position;
		*x->f_error = o->f_error;
		*x->counts = o->counts;
		*x->amp_fault = o->amp_fault;
		*x->home_sw = o->home_sw;
		*x->limit_pos = o->limit_pos;
		*x->limit_neg = o->limit_neg;
		/* index-enable is LinuxCNC's to set, the driver's to clear,
		 * and only by the read that took the mark: motion sets it
		 * between the read and the write, which must not see the
		 * read's answer to the pin as it was before */
		if (read_half && *x->index_enable && !o->index_enable)
			*x->index_enable = 0;
	}
	p->comp_id = t->card.comp.id;
	p->comp_sum = t->card.comp.sum;
	p->comp_tables = t->card.comp.tables;
}

/* A new reason the card stopped is worth one line in the log. */
static void report(struct instance *t)
{
	if (t->card.err[0] && strcmp(t->card.err, t->printed)) {
		rtapi_print_msg(RTAPI_MSG_ERR, "hal_sh2000: sh2000.%d: %s\n",
				t->card.index, t->card.err);
		rtapi_strlcpy(t->printed, t->card.err, sizeof(t->printed));
	} else if (!t->card.err[0]) {
		t->printed[0] = 0;
	}
}

static void read_funct(void *arg, long period)
{
	struct instance *t = arg;
	long long ref = rtapi_task_pll_get_reference();
	long late = ref ? (long)(rtapi_get_time() - ref) : 0;

	pins_in(t);
	hsc_read(&t->card, &t->in, &t->out, period, late);
	pins_out(t, 1);
	report(t);
}

static void write_funct(void *arg, long period)
{
	struct instance *t = arg;

	(void)period;
	pins_in(t);
	hsc_write(&t->card, &t->in, &t->out);
	/* the first card is the time master: the thread follows its clock */
	if (t->card.master)
		rtapi_task_pll_set_correction(t->out.pll_correction_ns);
	pins_out(t, 0);
	report(t);
}

/* The card's axes by the names the tools give them (sh2000ctl). */
static const char axis_name[SH2000_AXES] = { 'x', 'y', 'z', 'a' };

#define AXIS_PIN(type, dir, field, name) do { \
	r = hal_pin_##type##_newf(dir, &x->field, comp_id, \
				  "sh2000.%d.%c." name, n, axis_name[a]); \
	if (r < 0) \
		return r; \
} while (0)

/* index parameters, 0 by default: hostmot2's encoder ones of the same
 * names, and index-within (the driver's own) */
#define AXIS_PARAM(type, field, name) do { \
	r = hal_param_##type##_newf(HAL_RW, &x->field, comp_id, \
			       "sh2000.%d.%c." name, n, axis_name[a]); \
	if (r < 0) \
		return r; \
	x->field = 0; \
} while (0)

static int export_axis(int n, unsigned int a, struct pins_axis *x,
		       double scale)
{
	int r;

	AXIS_PIN(float, HAL_IN, position_cmd, "position-cmd");
	AXIS_PIN(float, HAL_OUT, position_fb, "position-fb");
	AXIS_PIN(float, HAL_OUT, f_error, "f-error");
	AXIS_PIN(float, HAL_OUT, encoder_position, "encoder-position");
	AXIS_PIN(s32, HAL_OUT, counts, "counts");
	AXIS_PIN(bit, HAL_IN, enable, "enable");
	AXIS_PIN(bit, HAL_OUT, amp_fault, "amp-fault");
	AXIS_PIN(bit, HAL_OUT, home_sw, "home-sw");
	AXIS_PIN(bit, HAL_OUT, limit_pos, "limit-pos");
	AXIS_PIN(bit, HAL_OUT, limit_neg, "limit-neg");
	AXIS_PIN(bit, HAL_IO, index_enable, "index-enable");
	AXIS_PARAM(bit, index_mask, "index-mask");
	AXIS_PARAM(bit, index_mask_invert, "index-mask-invert");
	AXIS_PARAM(bit, index_invert, "index-invert");
	AXIS_PARAM(float, index_within, "index-within");
	r = hal_param_float_newf(HAL_RW, &x->position_scale, comp_id,
				 "sh2000.%d.%c.position-scale", n, axis_name[a]);
	x->position_scale = scale;
	return r;
}

#define CARD_PIN(type, dir, field, name) do { \
	r = hal_pin_##type##_newf(dir, &p->field, comp_id, \
				  "sh2000.%d." name, n); \
	if (r < 0) \
		return r; \
} while (0)

/* zero until load_tables() loads a table */
static int export_comp(int n, struct pins_card *p)
{
	int r = hal_param_u32_newf(HAL_RO, &p->comp_id, comp_id,
				   "sh2000.%d.comp-id", n);

	if (r == 0)
		r = hal_param_u32_newf(HAL_RO, &p->comp_sum, comp_id,
				       "sh2000.%d.comp-sum", n);
	if (r == 0)
		r = hal_param_u32_newf(HAL_RO, &p->comp_tables, comp_id,
				       "sh2000.%d.comp-tables", n);
	return r;
}

static int export_card(int n, struct instance *t)
{
	struct pins_card *p = hal_malloc(sizeof(*p));
	char name[HAL_NAME_LEN + 1];
	unsigned int a;
	int r;

	if (!p)
		return -ENOMEM;
	memset(p, 0, sizeof(*p));
	t->p = p;
	CARD_PIN(bit, HAL_OUT, ok, "ok");
	CARD_PIN(bit, HAL_IN, estop, "estop");
	CARD_PIN(bit, HAL_OUT, fault, "fault");
	CARD_PIN(bit, HAL_IN, fault_reset, "fault-reset");
	CARD_PIN(s32, HAL_OUT, queue_fill, "queue-fill");
	CARD_PIN(s32, HAL_OUT, card_state, "card-state");
	CARD_PIN(u32, HAL_OUT, underruns, "underruns");
	CARD_PIN(u32, HAL_OUT, port_cycles, "port-cycles");
	CARD_PIN(s32, HAL_OUT, pll_correction_ns, "pll-correction-ns");
	CARD_PIN(float, HAL_OUT, delay_ms, "delay-ms");
	r = hal_param_s32_newf(HAL_RW, &p->queue_target, comp_id,
			       "sh2000.%d.queue-target", n);
	if (r < 0)
		return r;
	p->queue_target = HSC_QUEUE_TARGET;
	r = export_comp(n, p);
	if (r < 0)
		return r;
	for (a = 0; a < SH2000_AXES; a++) {
		r = export_axis(n, a, &p->axis[a], hsc_default_scale(&t->card, a));
		if (r < 0)
			return r;
	}
	rtapi_snprintf(name, sizeof(name), "sh2000.%d.read", n);
	r = hal_export_funct(name, read_funct, t, 1, 0, comp_id);
	if (r < 0)
		return r;
	rtapi_snprintf(name, sizeof(name), "sh2000.%d.write", n);
	return hal_export_funct(name, write_funct, t, 1, 0, comp_id);
}

static void close_all(void)
{
	int i;

	for (i = 0; i < ncards; i++)
		hsc_close(&inst[i].card);
	ncards = 0;
}

/* A soft limit the tables move the tool beyond (hsc_comp_reach()): at
 * RTAPI_MSG_ERR, so that it shows at LinuxCNC's default message level;
 * the start goes on, as sh2000ctl comp load's exit status stays 0. */
static void say_reach(void *ctx, const char *words)
{
	rtapi_print_msg(RTAPI_MSG_ERR, "hal_sh2000: sh2000.%d: comp: warning: %s\n",
			*(const int *)ctx, words);
}

/* comp=: every file checked against its card first, so a bad table on
 * any card changes no card's tables; then each loaded (the card at rest,
 * before the servo thread starts); its sh2000.N.comp-* say what is active. */
static int load_tables(void)
{
	char msg[512];
	int i, r, pass;

	for (pass = 0; pass < 2; pass++)
		for (i = 0; i < MAX_CARDS && comp[i]; i++) {
			if (!hsc_comp_wanted(comp[i]))
				continue;
			if (i >= ncards) {
				rtapi_print_msg(RTAPI_MSG_ERR,
						"hal_sh2000: comp: %s: no card sh2000.%d (device=)\n",
						comp[i], i);
				return -EINVAL;
			}
			r = pass ? hsc_comp_load(&inst[i].card, comp[i], msg, sizeof(msg)) :
				   hsc_comp_check(&inst[i].card, comp[i], msg, sizeof(msg));
			if (r < 0) {
				rtapi_print_msg(RTAPI_MSG_ERR,
						"hal_sh2000: sh2000.%d: comp: %s\n", i, msg);
				return r;
			}
			if (pass && hsc_comp_reach(&inst[i].card, comp[i], say_reach, &i,
						   msg, sizeof(msg)) < 0)
				rtapi_print_msg(RTAPI_MSG_ERR,
						"hal_sh2000: sh2000.%d: comp: %s\n", i, msg);
			if (pass) {
				inst[i].p->comp_id = inst[i].card.comp.id;
				inst[i].p->comp_sum = inst[i].card.comp.sum;
				inst[i].p->comp_tables = inst[i].card.comp.tables;
			}
			rtapi_print_msg(RTAPI_MSG_INFO, pass ?
					"hal_sh2000: sh2000.%d: tables of %s active\n" :
					"hal_sh2000: sh2000.%d: %s checked\n", i, comp[i]);
		}
	return 0;
}

int rtapi_app_main(void)
{
	char msg[256];
	int i, r;

	comp_id = hal_init("hal_sh2000");
	if (comp_id < 0)
		return comp_id;
	for (i = 0; i < MAX_CARDS && device[i] && device[i][0]; i++) {
		if (!strcmp(device[i], "sim")) {
			rtapi_print_msg(RTAPI_MSG_ERR,
					"hal_sh2000: sh2000.%d: sim is a card in virtual time, not for a real-time thread: serve one with sh2000-sim NAME and give sim:NAME\n",
					i);
			r = -EINVAL;
			goto fail;
		}
		r = hsc_open(&inst[i].card, i, device[i], msg, sizeof(msg));
		if (r < 0) {
			rtapi_print_msg(RTAPI_MSG_ERR, "hal_sh2000: sh2000.%d: %s\n",
					i, msg);
			goto fail;
		}
		ncards = i + 1;
		r = export_card(i, &inst[i]);
		if (r < 0) {
			rtapi_print_msg(RTAPI_MSG_ERR,
					"hal_sh2000: sh2000.%d: exporting pins failed (%d)\n",
					i, r);
			goto fail;
		}
	}
	r = load_tables();
	if (r < 0)
		goto fail;
	for (i = 0; i < ncards; i++) {
		r = hsc_comp_watch_start(&inst[i].card, HSC_COMP_WATCH_MS, msg,
					 sizeof(msg));
		if (r < 0) {
			rtapi_print_msg(RTAPI_MSG_ERR, "hal_sh2000: sh2000.%d: %s\n",
					i, msg);
			goto fail;
		}
	}
	if (!ncards) {
		rtapi_print_msg(RTAPI_MSG_ERR,
				"hal_sh2000: no card: give device=/dev/sh2000-0[,sim:NAME,...]\n");
		r = -EINVAL;
		goto fail;
	}
	rtapi_print_msg(RTAPI_MSG_INFO, "hal_sh2000: %d card(s)\n", ncards);
	hal_ready(comp_id);
	return 0;
fail:
	close_all();
	hal_exit(comp_id);
	return r;
}

void rtapi_app_exit(void)
{
	close_all();
	hal_exit(comp_id);
}
