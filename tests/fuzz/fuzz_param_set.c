// SPDX-License-Identifier: MIT
/*
 * sh2000_param_set() on the in-process simulated card (`sim`) with
 * arbitrary axes, parameter ids and values. Each input is a list of up to
 * MAX_RECORDS 10-byte records (enough for the interplay of scale, soft
 * limits and timing; each call costs the card model servo cycles): axis (byte % 6 - 1: SH2000_GLOBAL, 0..3, and 4 which
 * does not exist), id (byte % 40), and 8 bytes that are the value: as a
 * double if the axis byte's top bit is set, else a small decimal number
 * (-1000.00 .. 1000.00 from the first four bytes) so that valid values
 * are common too.
 *
 * Promises checked after every call: success only for a valid axis and
 * id, and then the card reads back the value as the card stores it (a
 * binary32 or whole counts); failure with a message, and then nothing
 * changed on the card (the harness keeps a copy of every parameter). The
 * card keeps answering. At the end of each input
 * the calls are undone in reverse order (each undo must succeed: it goes
 * back through states the card accepted), so inputs do not leak into one
 * another.
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <sh2000/sh2000.h>

#include "fuzz.h"

#define RECORD		10
#define MAX_RECORDS	8

struct undo {
	int axis;
	unsigned int id;
	double old;
};

static struct sh2000 *card;
/* What the card holds, in user units, by section (0 global, 1 + axis):
 * read once, then kept up to date, so each call costs one look */
static double shadow[SH2000_AXES + 1][SH2000_GP_END];

static double get(int axis, unsigned int id)
{
	double v;
	int r = sh2000_param_get(card, axis, id, &v);

	if (r < 0)
		fz_fail("get axis %d param %u: %s", axis, id,
			sh2000_last_error(card));
	return v;
}

static int is_mm(unsigned int id)
{
	const char *unit = sh2000_param_unit(id);

	return unit && !strncmp(unit, "mm", 2);
}

/* An axis' lengths, speeds and accelerations after its scale changed:
 * the card keeps counts, the library converts with the new scale. */
static void reread_mm(int axis)
{
	for (unsigned int id = 0; id < SH2000_AXIS_PARAMS; id++)
		if (is_mm(id))
			shadow[axis + 1][id] = get(axis, id);
}

int LLVMFuzzerInitialize(int *argc, char ***argv);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	char msg[256];

	(void)argc;
	(void)argv;
	if (sh2000_open(&card, "sim", msg, sizeof(msg)) < 0)
		fz_fail("sim: %s", msg);
	for (unsigned int id = SH2000_GP_FIRST; id < SH2000_GP_END; id++)
		shadow[0][id] = get(SH2000_GLOBAL, id);
	for (int a = 0; a < (int)SH2000_AXES; a++)
		for (unsigned int id = 0; id < SH2000_AXIS_PARAMS; id++)
			shadow[a + 1][id] = get(a, id);
	return 0;
}

static int valid(int axis, unsigned int id)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	if (!p)
		return 0;
	if (id >= SH2000_GP_FIRST)
		return axis == SH2000_GLOBAL;
	return axis >= 0 && axis < (int)SH2000_AXES;
}

/* How far the read-back may be from what was set: the card keeps
 * binary32 (relative 2^-24) or whole counts (half a count in mm). */
static double tolerance(int axis, unsigned int id, double v)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	if (p->type == SH2000_PT_F32)
		return fabs(v) * 1.2e-7;
	return is_mm(id) ? 0.5000001 / shadow[axis + 1][SH2000_P_SCALE] : 0.0;
}

static double value_of(const uint8_t *rec)
{
	double v;
	int32_t i;

	if (rec[0] & 0x80) {
		memcpy(&v, rec + 2, sizeof(v));
		return v;
	}
	memcpy(&i, rec + 2, sizeof(i));
	return (double)(i % 100001) / 100.0;
}

/* One call; returns 1 if it changed something to undo. */
static int one(int axis, unsigned int id, double v, struct undo *u)
{
	int ok = valid(axis, id), r;
	double *held = ok ? &shadow[axis + 1][id] : NULL, after;

	r = sh2000_param_set(card, axis, id, v);
	if (r == 0 && !ok)
		fz_fail("axis %d param %u: set succeeded", axis, id);
	if (r > 0 || r == -ETIMEDOUT || r == -SH2000_ETIMEOUT)
		fz_fail("axis %d param %u = %g: returned %d (%s)", axis, id, v,
			r, sh2000_last_error(card));
	if (r < 0 && !sh2000_last_error(card)[0])
		fz_fail("axis %d param %u = %g: failed (%d) without a message",
			axis, id, v, r);
	if (!ok)
		return 0;
	after = get(axis, id);
	if (r < 0) {
		if (memcmp(&after, held, sizeof(after)))
			fz_fail("axis %d param %u = %g failed (%s) but changed %.17g to %.17g",
				axis, id, v, sh2000_last_error(card), *held,
				after);
		return 0;
	}
	if (!(fabs(after - v) <= tolerance(axis, id, v)))
		fz_fail("axis %d param %u = %.17g reads back %.17g", axis, id,
			v, after);
	u->axis = axis;
	u->id = id;
	u->old = *held;
	*held = after;
	if (id == SH2000_P_SCALE)
		reread_mm(axis);
	return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct undo undo[MAX_RECORDS];
	size_t n = 0;

	for (size_t i = 0; i + RECORD <= size && n < MAX_RECORDS; i += RECORD) {
		int axis = (data[i] & 0x7f) % 6 - 1;
		unsigned int id = data[i + 1] % 40u;

		n += one(axis, id, value_of(data + i), &undo[n]);
	}
	while (n--) {
		const struct undo *u = &undo[n];

		if (sh2000_param_set(card, u->axis, u->id, u->old) < 0)
			fz_fail("undo axis %d param %u = %.17g: %s", u->axis,
				u->id, u->old, sh2000_last_error(card));
		if (memcmp(&u->old, &(double){ get(u->axis, u->id) },
			   sizeof(double)))
			fz_fail("undo axis %d param %u = %.17g reads back otherwise",
				u->axis, u->id, u->old);
		shadow[u->axis + 1][u->id] = u->old;
		if (u->id == SH2000_P_SCALE)
			reread_mm(u->axis);
	}
	if (sh2000_nop(card) < 0)
		fz_fail("the card stopped answering: %s",
			sh2000_last_error(card));
	return 0;
}
