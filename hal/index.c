// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * index-enable with hostmot2's encoder semantics (docs/linuxcnc.md
 * "Homing on the index"): LinuxCNC sets it true to arm; the driver arms
 * the card's index latch (INDEX_ARM, protocol 1.6) with index-mask,
 * index-mask-invert and index-invert (and index-within, the travel it
 * allows for the mark: the driver's own), while the card runs the stream;
 * when the card reports the mark, the driver takes the counter at the
 * mark as the axis' new zero and writes index-enable false in the same
 * read: from then on position-fb is zero at the mark, continuous, and the
 * commands are shifted by the same counts, so the card does not move.
 *
 * An arm that cannot be honoured (a card older than 1.6, a refused arm,
 * an arm the card ended without a mark, none within index-within) never
 * clears index-enable: the axis shows amp-fault (LinuxCNC: "joint N
 * amplifier fault", homing aborted) with the reason in the log, until the
 * joint is disabled or fault-reset is raised.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "hsc.h"

/* The axis faults with the reason in the driver's message; axes failing
 * in one read share it (homing arms them together), so each is named. */
static void fail(struct hsc_card *c, unsigned int a, const char *why)
{
	struct hsc_index *ix = &c->ix[a];
	size_t n = strlen(c->err);
	char letter = (char)(SH2000_AXIS_LETTERS[a] + ('a' - 'A'));

	ix->phase = HSC_IX_IDLE;
	ix->fault = 1;
	if (c->ix_fail_tick == c->tick + 1 && n + 2 < sizeof(c->err))
		snprintf(c->err + n, sizeof(c->err) - n, "; %c: index-enable: %s",
			 letter, why);
	else
		snprintf(c->err, sizeof(c->err), "%c: index-enable: %s",
			 letter, why);
	c->ix_fail_tick = c->tick + 1;
}

static unsigned int arm_flags(const struct hsc_axis_in *in)
{
	unsigned int f = 0;

	if (in->index_mask)
		f |= SH2000_INDEX_F_MASK;
	if (in->index_mask && in->index_mask_invert)
		f |= SH2000_INDEX_F_MASK_INVERT;
	if (in->index_invert)
		f |= SH2000_INDEX_F_RISING;
	return f;
}

/* index-within in counts of the card (0: no limit; beyond 32 bits, or
 * not a number: no limit either, the card's ARG is a 32-bit travel). */
static int32_t within_counts(const struct hsc_axis_in *in)
{
	double c = fabs(in->index_within * in->position_scale);

	return isfinite(c) && c < INT32_MAX ? (int32_t)nearbyint(c) : 0;
}

/* One command through the card's one slot (write.c's commands wait). */
static int start(struct hsc_card *c, unsigned int op, unsigned int a,
		 unsigned int flags, int32_t arg)
{
	int r;

	if (c->cmd_busy)
		return -EAGAIN;
	r = sh2000_command_start(c->h, op, a, flags, arg);
	if (r == 0) {
		c->cmd_busy = 1;
		c->cmd_op = op;
		c->cmd_arg = a;
	}
	return r;
}

static void arm(struct hsc_card *c, const struct hsc_in *in, unsigned int a)
{
	int r;

	/* as hostmot2 does, a request waits for the encoder to run */
	if (!c->streaming || !(hsc_enabled(&c->st) & (1u << a)))
		return;
	if (sh2000_index_supported(c->h) < 0) {
		fail(c, a, sh2000_last_error(c->h));
		return;
	}
	r = start(c, SH2000_CMD_INDEX_ARM, a, arm_flags(&in->axis[a]),
		  within_counts(&in->axis[a]));
	if (r == 0)
		c->ix[a].phase = HSC_IX_ARMING;
	else if (r != -EAGAIN)
		fail(c, a, sh2000_last_error(c->h));
}

void hsc_index_answer(struct hsc_card *c, int r, int32_t value)
{
	unsigned int a = c->cmd_arg;

	if (a >= SH2000_AXES || c->cmd_op != SH2000_CMD_INDEX_ARM ||
	    c->ix[a].phase != HSC_IX_ARMING)
		return;		/* a disarm: nothing waits for it */
	if (r < 0) {
		fail(c, a, sh2000_last_error(c->h));
		return;
	}
	c->ix[a].arm = (unsigned int)value & 0xffffu;
	c->ix[a].phase = HSC_IX_ARMED;
}

/* The arm has ended on the card (INDEX_ARMED gone): what became of it. */
static void ended(struct hsc_card *c, unsigned int a)
{
	struct sh2000_index r;
	int e = sh2000_index_read(c->h, a, &c->st, &r);

	if (e == -EAGAIN)
		return;		/* torn or busy: the next tick */
	if (e < 0) {
		fail(c, a, sh2000_last_error(c->h));
		return;
	}
	if (r.arm != c->ix[a].arm) {
		fail(c, a, "another program re-armed the card's index latch");
		return;
	}
	switch (r.state) {
	case SH2000_INDEX_ARMED:
		/* still armed: the status snapshot is older than the arm
		 * (the answer comes at once, the snapshot every few cycles) */
		return;
	case SH2000_INDEX_LATCHED:
		c->ix[a].offset = r.counts;
		c->ix[a].have_offset = 1;
		c->ix[a].phase = HSC_IX_IDLE;
		c->ix[a].latched = 1;
		return;
	case SH2000_INDEX_MISSED:
		fail(c, a, "no index mark within the arm's travel");
		return;
	default:
		fail(c, a, "the card ended the arm without a mark (axis disabled, fault or emergency stop)");
	}
}

void hsc_index_read(struct hsc_card *c, const struct hsc_in *in)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct hsc_index *ix = &c->ix[a];
		int want = in->axis[a].index_enable;

		ix->latched = 0;
		if (ix->fault && (!in->axis[a].enable || in->fault_reset))
			ix->fault = 0;
		switch (ix->phase) {
		case HSC_IX_IDLE:
			if (want && !ix->fault && !ix->want_last)
				arm(c, in, a);
			break;
		case HSC_IX_ARMING:
			break;		/* hsc_index_answer */
		case HSC_IX_ARMED:
			if (!want) {	/* LinuxCNC withdrew it */
				if (start(c, SH2000_CMD_INDEX_DISARM, a, 0, 0) != -EAGAIN)
					ix->phase = HSC_IX_IDLE;
			} else if (!(c->st.axis[a].state & SH2000_AXIS_INDEX_ARMED)) {
				ended(c, a);
			}
			break;
		}
		/* taken: armed, latched this tick, or failed (a true pin
		 * arms again once the fault is cleared) */
		ix->want_last = want && (ix->phase != HSC_IX_IDLE || ix->fault ||
					 ix->latched);
	}
}

double hsc_index_offset(const struct hsc_card *c, unsigned int a)
{
	return c->ix[a].have_offset ? (double)c->ix[a].offset : 0.0;
}

void hsc_index_command(const struct hsc_card *c, struct hsc_in *in)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double k = in->axis[a].position_scale;

		if (c->ix[a].have_offset && k != 0)
			in->axis[a].position_cmd += (double)c->ix[a].offset / k;
	}
}
