// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000's index-enable (hal/index.c) without LinuxCNC: a loop that
 * plays LinuxCNC's servo thread against the card model in virtual time,
 * as test_hsc.c does, and homes axis x on the index as LinuxCNC's homing
 * does: it creeps towards the mark at the home switch, sets index-enable,
 * and on the tick the driver clears it takes position-fb as the mark's
 * coordinate. Checks that index-enable is cleared only at the mark, that
 * position-fb is then zero at the mark (the scale's physical mark, not
 * where the card powered up), continuous, and that the card's set-point
 * does not jump. And the requests that cannot be honoured: a card older
 * than protocol 1.6, a mark that does not come within index-within: the
 * axis shows amp-fault with the reason, index-enable stays true, until
 * the axis is disabled.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "hsc.h"
#include "sh2000/sim.h"
#include "sh2000_internal.h"	/* the card's protocol version, to age it */

#define PERIOD_NS	1000000L
#define SCALE		100000.0	/* counts per mm, the card's default */
#define START_MM	300.0		/* the model's carriage at power-up */

struct rig {
	struct hsc_card c;
	struct hsc_in pins;	/* as LinuxCNC sets the pins */
	struct hsc_out out;
	uint64_t t_next;
	char log[1024];		/* the driver's messages, as it prints them */
};

/* What hal_sh2000.c's report() prints after a read: the message when it
 * changed. */
static void report(struct rig *r)
{
	size_t n = strlen(r->log);
	const char *last = strrchr(r->log, '\n');

	if (!r->c.err[0])
		return;
	last = last ? last : r->log;
	if (n && !strcmp(r->c.err, last == r->log ? r->log : last + 1))
		return;
	snprintf(r->log + n, sizeof(r->log) - n, "%s%s", n ? "\n" : "", r->c.err);
}

/* One servo period as hal_sh2000.c runs it: the pins shifted by the
 * index offset (hsc_index_command), read, motion, write. */
static void tick(struct rig *r, double cmd)
{
	struct hsc_in in;
	uint64_t now = sh2000_now_ns(r->c.h);

	if (now < r->t_next)
		sh2000_sleep_ns(r->c.h, r->t_next - now);
	now = sh2000_now_ns(r->c.h);
	in = r->pins;
	hsc_index_command(&r->c, &in);
	hsc_read(&r->c, &in, &r->out, PERIOD_NS, (long)(now - r->t_next));
	report(r);
	r->t_next += PERIOD_NS;
	/* the driver writes index-enable false; LinuxCNC's homing sees it
	 * in the same period and commands from position-fb, in the mark's
	 * frame (HOME_SET_INDEX_POSITION: pos_cmd = pos_fb) */
	if (r->pins.axis[0].index_enable && !r->out.axis[0].index_enable) {
		r->pins.axis[0].index_enable = 0;
		cmd = r->out.axis[0].position_fb;
	}
	r->pins.axis[0].position_cmd = cmd;
	if (r->pins.axis[1].enable)	/* y along with x */
		r->pins.axis[1].position_cmd = cmd;
	in = r->pins;
	hsc_index_command(&r->c, &in);
	hsc_write(&r->c, &in, &r->out);
}

static void home_on_index(void **state)
{
	struct rig *r = calloc(1, sizeof(*r));
	char msg[256];
	double cmd, fb_before = 0, step = 1.0 / 1000.0;	/* 1 mm/s */
	int32_t sp_before = 0;
	int n, latched = -1;

	(void)state;
	assert_non_null(r);
	if (hsc_open(&r->c, 0, "sim", msg, sizeof(msg)) < 0)
		fail_msg("hsc_open: %s", msg);
	r->pins.axis[0].position_scale = SCALE;
	r->pins.axis[0].enable = 1;
	r->pins.axis[0].index_mask = 1;	/* only the mark on the switch */
	r->t_next = sh2000_now_ns(r->c.h);
	/* at the home switch (physical 0 mm, 300 mm below the start) as
	 * LinuxCNC's latch move leaves it: just on it */
	cmd = -300.05;
	for (n = 0; n < 100 && !r->c.streaming; n++)
		tick(r, 0.0);
	assert_true(r->c.streaming);
	for (n = 0; n < 3000; n++)	/* a slow approach, 1 mm in 10 ms steps */
		tick(r, fmax(cmd, -(double)(n + 1) * 0.1));
	for (n = 0; n < 300; n++)
		tick(r, cmd);
	assert_true(r->out.ok);
	assert_true(r->out.axis[0].home_sw);
	/* index-enable: the next mark on the switch is at physical -1 mm */
	r->pins.axis[0].index_enable = 1;
	for (n = 0; n < 3000 && latched < 0; n++) {
		fb_before = r->out.axis[0].position_fb;
		sp_before = r->c.st.axis[0].cmd_counts;
		cmd -= step;
		tick(r, cmd);
		if (!r->pins.axis[0].index_enable)
			latched = n;
		else
			assert_false(r->out.axis[0].amp_fault);
	}
	assert_true(latched >= 0);
	assert_true(r->out.ok);
	/* armed about 50 ms, the mark 0.95 mm on at 1 mm/s */
	assert_true(latched > 900 && latched < 1100);
	/* the zero is the scale's mark, in card counts from power-up */
	assert_true(fabs(hsc_index_offset(&r->c, 0) - (-1.0 - START_MM) * SCALE) <= 1.0);
	/* position-fb continuous: the old value less the mark, within the
	 * tick's travel */
	assert_true(fabs(r->out.axis[0].position_fb -
			 (fb_before - (-1.0 - START_MM))) < 2 * step);
	/* LinuxCNC now commands in the mark's frame: the card does not jump
	 * (it plays what was queued, 1 mm/s for the queue's ~8 ms: some 800
	 * counts; a frame error would be 30 100 000) */
	cmd = r->out.axis[0].position_fb;
	for (n = 0; n < 50; n++) {
		tick(r, cmd);
		assert_true(abs(r->c.st.axis[0].cmd_counts - sp_before) < 1500);
	}
	for (n = 0; n < 500; n++)
		tick(r, cmd);
	/* at rest: position-fb is the encoder from the mark */
	assert_true(fabs(r->out.axis[0].position_fb * SCALE -
			 ((double)r->c.st.axis[0].pos_counts -
			  hsc_index_offset(&r->c, 0))) <= 1.0);
	assert_true(fabs(r->out.axis[0].position_fb - cmd) < 1e-4);
	assert_false(r->out.axis[0].amp_fault);
	hsc_close(&r->c);
	free(r);
}

/* A card streaming with axes x and y enabled (y commanded as x), at rest
 * where it powered up (300 mm from the switch: no mark on the switch
 * within reach). */
static struct rig *streaming(void)
{
	struct rig *r = calloc(1, sizeof(*r));
	char msg[256];
	int n;

	assert_non_null(r);
	if (hsc_open(&r->c, 0, "sim", msg, sizeof(msg)) < 0)
		fail_msg("hsc_open: %s", msg);
	r->pins.axis[0].position_scale = SCALE;
	r->pins.axis[0].enable = 1;
	r->pins.axis[1].position_scale = SCALE;
	r->pins.axis[1].enable = 1;
	r->t_next = sh2000_now_ns(r->c.h);
	for (n = 0; n < 100 && !r->c.streaming; n++)
		tick(r, 0.0);
	assert_true(r->c.streaming);
	return r;
}

static void rig_close(struct rig *r)
{
	hsc_close(&r->c);
	free(r);
}

/* A fault of x that LinuxCNC sees: amp-fault, index-enable still true,
 * the reason in the driver's messages; gone once the axis is disabled. */
static void shows_fault(struct rig *r, const char *reason)
{
	char want[256];
	int n;

	assert_true(r->out.axis[0].amp_fault);
	assert_true(r->pins.axis[0].index_enable);
	assert_true(r->out.axis[0].index_enable);
	snprintf(want, sizeof(want), "x: index-enable: %s", reason);
	if (!strstr(r->log, "x: index-enable: ") || !strstr(r->log, reason))
		fail_msg("the driver's messages \"%s\" do not say \"%s\"", r->log, want);
	r->pins.axis[0].enable = 0;
	r->pins.axis[0].index_enable = 0;
	for (n = 0; n < 5; n++)
		tick(r, 0.0);
	assert_false(r->out.axis[0].amp_fault);
}

static void older_card(void **state)
{
	struct rig *r = streaming();
	int n;

	(void)state;
	/* the card as one that speaks 1.5: no INDEX_ARM */
	r->c.h->card_version = SH2000_PROTO_VERSION_MAJOR(SH2000_PROTO_VERSION) << 8 | 5u;
	assert_false(r->out.axis[0].amp_fault);
	r->pins.axis[0].index_enable = 1;
	for (n = 0; n < 20; n++)
		tick(r, 0.0);
	shows_fault(r, "protocol 1.5: arming the index latch while it runs needs 1.6");
	rig_close(r);
}

static void no_mark_within(void **state)
{
	struct rig *r = streaming();
	double cmd = 0.0, step = 1.0 / 1000.0;	/* 1 mm/s */
	int n;

	(void)state;
	/* off the switch with index-mask: no mark counts; 0.5 mm allowed;
	 * x and y together, as LinuxCNC homes joints at once */
	for (n = 0; n < 2; n++) {
		r->pins.axis[n].index_mask = 1;
		r->pins.axis[n].index_within = 0.5;
		r->pins.axis[n].index_enable = 1;
	}
	for (n = 0; n < 400; n++) {	/* 0.4 mm: still armed */
		cmd -= step;
		tick(r, cmd);
	}
	assert_false(r->out.axis[0].amp_fault);
	assert_int_equal(r->c.ix[0].phase, HSC_IX_ARMED);
	/* some 0.5 mm + the queue's delay on: the card gives up */
	for (n = 0; n < 200 && !r->out.axis[0].amp_fault; n++) {
		cmd -= step;
		tick(r, cmd);
	}
	assert_true(r->out.axis[0].amp_fault);
	assert_true(r->out.axis[1].amp_fault);
	assert_true(r->out.ok);		/* the card runs on: LinuxCNC stops */
	/* the driver's messages name both */
	if (!strstr(r->log, "x: index-enable: no index mark") ||
	    !strstr(r->log, "y: index-enable: no index mark"))
		fail_msg("the messages do not name both axes: %s", r->log);
	shows_fault(r, "no index mark within the arm's travel");
	rig_close(r);
}

/* The arm's answer comes at once, the status snapshot every few cycles:
 * a snapshot from before the arm (INDEX_ARMED not yet set) must not read
 * as an arm the card ended. */
static void status_older_than_arm(void **state)
{
	struct rig *r = streaming();
	int n;

	(void)state;
	r->pins.axis[0].index_enable = 1;
	for (n = 0; n < 20 && r->c.ix[0].phase != HSC_IX_ARMED; n++)
		tick(r, 0.0);
	assert_int_equal(r->c.ix[0].phase, HSC_IX_ARMED);
	r->c.st.axis[0].state &= (uint16_t)~SH2000_AXIS_INDEX_ARMED;
	hsc_index_read(&r->c, &r->pins);
	assert_int_equal(r->c.ix[0].phase, HSC_IX_ARMED);
	assert_false(r->c.ix[0].fault);
	for (n = 0; n < 20; n++)
		tick(r, 0.0);
	assert_false(r->out.axis[0].amp_fault);
	assert_true(r->out.axis[0].index_enable);
	rig_close(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(home_on_index),
		cmocka_unit_test(older_card),
		cmocka_unit_test(no_mark_within),
		cmocka_unit_test(status_older_than_arm),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
