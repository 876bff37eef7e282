// SPDX-License-Identifier: MIT
/*
 * Compensation tables on the card (protocol 1.5, docs/compensation.md):
 * the load (BEGIN, PAGE, COMMIT into a staging memory, checked with the
 * protocol's own rules against this card's parameters), the switch at rest
 * with a blend from the old corrections to the new, and each servo cycle's
 * correction of the set-points. The host's path stays nominal: the
 * snapshot reports the nominal set-point and the counter with the
 * correction taken out; only the loop sees the corrected set-point.
 */
#include <math.h>
#include <string.h>

#include "cardmodel.h"

#define RD(fw, w)	sh2000_board_ram_read((fw)->hw, (w))
#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))

static void publish(struct sh2000_dsp *fw)
{
	const struct sh2000_fw_comp *c = &fw->comp;
	uint16_t s[SH2000_COMP_STATUS_WORDS];
	unsigned int i;

	s[SH2000_CS_STATE] = c->blend < 1.0 ? SH2000_COMP_SWITCHING :
			     c->has[c->cur] ? SH2000_COMP_ACTIVE : SH2000_COMP_NONE;
	s[SH2000_CS_TABLES] = c->has[c->cur] ? (uint16_t)c->ix[c->cur].tables : 0;
	s[SH2000_CS_ID_LO] = c->has[c->cur] ? (uint16_t)(c->ix[c->cur].id & 0xffffu) : 0;
	s[SH2000_CS_ID_HI] = c->has[c->cur] ? (uint16_t)(c->ix[c->cur].id >> 16) : 0;
	s[SH2000_CS_SUM_LO] = c->has[c->cur] ? (uint16_t)(c->sum[c->cur] & 0xffffu) : 0;
	s[SH2000_CS_SUM_HI] = c->has[c->cur] ? (uint16_t)(c->sum[c->cur] >> 16) : 0;
	s[SH2000_CS_GEN] = c->gen;
	s[SH2000_CS_CHECK] = sh2000_check16(s, SH2000_CS_CHECK);
	/* CHECK first, then the rest: a host reading upwards meanwhile sees
	 * a mismatch and reads again */
	WR(fw, SH2000_W_COMP_STATUS + SH2000_CS_CHECK, s[SH2000_CS_CHECK]);
	for (i = 0; i < SH2000_CS_CHECK; i++)
		WR(fw, SH2000_W_COMP_STATUS + i, s[i]);
}

void sh2000_comp_boot(struct sh2000_dsp *fw)
{
	struct sh2000_fw_comp *c = &fw->comp;

	c->stage_words = c->stage_got = 0;
	c->has[0] = c->has[1] = 0;
	c->cur = 0;
	c->blend = 1.0;
	c->gen = 0;
	memset(c->off, 0, sizeof(c->off));
	memset(c->v, 0, sizeof(c->v));
	memset(c->a, 0, sizeof(c->a));
	publish(fw);
}

static uint16_t refuse(uint32_t *value, int table, int point,
		       enum sh2000_comp_reason r, uint16_t res)
{
	*value = SH2000_COMP_FAULT(table < 0 ? 0xff : table,
				   point < 0 ? 0xffff : point, r);
	return res;
}

static uint16_t page(struct sh2000_dsp *fw, uint16_t count, uint32_t first,
		     uint32_t *value)
{
	struct sh2000_fw_comp *c = &fw->comp;
	uint16_t w[SH2000_COMP_PAGE_WORDS];
	unsigned int i;

	if (!c->stage_words || first != c->stage_got || !count ||
	    count > SH2000_COMP_PAGE_WORDS || first + count > c->stage_words)
		return refuse(value, -1, -1, SH2000_COMP_R_PAGES,
			      SH2000_RES_BAD_VALUE);
	for (i = 0; i < count; i++)
		w[i] = RD(fw, SH2000_W_COMP_PAGE + 1u + i);
	if (RD(fw, SH2000_W_COMP_PAGE) != sh2000_comp_page_check(first, w, count))
		return SH2000_RES_CHECKSUM;	/* the host sends it again */
	memcpy(&c->stage[first], w, count * sizeof(w[0]));
	c->stage_got += count;
	return SH2000_RES_OK;
}

static void limits_of(const struct sh2000_dsp *fw, struct sh2000_comp_limits *l)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		l->vmax[a] = fw->ax[a].prm.vmax;
		l->amax[a] = fw->ax[a].prm.amax;
	}
}

/* The staged image checked whole; then, at rest, it becomes the active
 * set and the corrections blend towards it. */
static uint16_t commit(struct sh2000_dsp *fw, uint32_t sum, uint32_t *value)
{
	struct sh2000_fw_comp *c = &fw->comp;
	struct sh2000_comp_index ix;
	struct sh2000_comp_limits lim;
	struct sh2000_comp_fault why;
	unsigned int next = 1u - c->cur;

	if (!c->stage_words || c->stage_got != c->stage_words)
		return refuse(value, -1, -1, SH2000_COMP_R_PAGES,
			      SH2000_RES_BAD_VALUE);
	if (sh2000_comp_sum(c->stage, c->stage_words) != sum)
		return refuse(value, -1, -1, SH2000_COMP_R_SUM,
			      SH2000_RES_CHECKSUM);
	limits_of(fw, &lim);
	if (sh2000_comp_parse(c->stage, c->stage_words, &ix, &why) ||
	    sh2000_comp_check(c->stage, &ix, &lim, &why))
		return refuse(value, why.table, why.point, why.reason,
			      SH2000_RES_BAD_VALUE);
	if (sh2000_fw_in_motion(fw) || c->blend < 1.0)
		return SH2000_RES_BUSY;	/* staging kept: COMMIT again */
	memcpy(c->img[next], c->stage, c->stage_words * sizeof(c->stage[0]));
	c->ix[next] = ix;
	c->sum[next] = sum;
	c->has[next] = 1;
	c->cur = next;
	c->blend = 0.0;
	c->gen++;
	publish(fw);
	return SH2000_RES_OK;
}

static uint16_t clear(struct sh2000_dsp *fw)
{
	struct sh2000_fw_comp *c = &fw->comp;

	if (sh2000_fw_in_motion(fw) || c->blend < 1.0)
		return SH2000_RES_BUSY;
	c->stage_words = c->stage_got = 0;
	if (!c->has[c->cur])
		return SH2000_RES_OK;
	c->cur = 1u - c->cur;
	c->has[c->cur] = 0;
	c->blend = 0.0;
	c->gen++;
	publish(fw);
	return SH2000_RES_OK;
}

uint16_t sh2000_comp_command(struct sh2000_dsp *fw, uint16_t op,
			     uint16_t param, uint32_t arg, uint32_t *value)
{
	struct sh2000_fw_comp *c = &fw->comp;

	switch (op) {
	case SH2000_CMD_COMP_BEGIN:
		c->stage_words = c->stage_got = 0;
		if (arg < SH2000_COMP_HEADER_WORDS || arg > SH2000_COMP_MAX_WORDS)
			return refuse(value, -1, -1, SH2000_COMP_R_SIZE,
				      SH2000_RES_BAD_VALUE);
		c->stage_words = arg;
		return SH2000_RES_OK;
	case SH2000_CMD_COMP_PAGE:
		return page(fw, param, arg, value);
	case SH2000_CMD_COMP_COMMIT:
		return commit(fw, arg, value);
	default:	/* SH2000_CMD_COMP_CLEAR */
		return clear(fw);
	}
}

static void set_offsets(const struct sh2000_fw_comp *c, unsigned int set,
			const double pos[SH2000_AXES], double off[SH2000_AXES])
{
	unsigned int a;

	if (c->has[set]) {
		sh2000_comp_eval(c->img[set], &c->ix[set], pos, off);
		return;
	}
	for (a = 0; a < SH2000_AXES; a++)
		off[a] = 0.0;
}

/* The blended corrections at the nominal positions pos: the active set,
 * or during a switch the smoothstep from the set before (no step in the
 * set-point or its velocity). */
static void offsets_at(const struct sh2000_fw_comp *c,
		       const double pos[SH2000_AXES], double off[SH2000_AXES])
{
	double before[SH2000_AXES], s;
	unsigned int a;

	set_offsets(c, c->cur, pos, off);
	if (c->blend >= 1.0)
		return;
	s = c->blend * c->blend * (3.0 - 2.0 * c->blend);
	set_offsets(c, 1u - c->cur, pos, before);
	for (a = 0; a < SH2000_AXES; a++)
		off[a] = before[a] + s * (off[a] - before[a]);
}

void sh2000_comp_cycle(struct sh2000_dsp *fw, double T)
{
	struct sh2000_fw_comp *c = &fw->comp;
	double pos[SH2000_AXES], now[SH2000_AXES];
	double blend_s = SH2000_COMP_BLEND_MS * 1e-3;
	unsigned int a;

	if (!c->has[0] && !c->has[1])
		return;		/* never loaded: nothing to do */
	for (a = 0; a < SH2000_AXES; a++)
		pos[a] = fw->ax[a].cmd;
	if (c->blend < 1.0) {
		c->blend = fmin(1.0, c->blend + T / blend_s);
		if (c->blend >= 1.0)
			publish(fw);
	}
	offsets_at(c, pos, now);
	for (a = 0; a < SH2000_AXES; a++) {
		double v = (now[a] - c->off[a]) / T;

		c->a[a] = (v - c->v[a]) / T;
		c->v[a] = v;
		c->off[a] = now[a];
	}
}

/* The corrections at the nominal set-points as they are, axis a's at x. */
static void offsets_with(const struct sh2000_dsp *fw, unsigned int a, double x,
			 double off[SH2000_AXES])
{
	double pos[SH2000_AXES];
	unsigned int i;

	for (i = 0; i < SH2000_AXES; i++)
		pos[i] = fw->ax[i].cmd;
	pos[a] = x;
	offsets_at(&fw->comp, pos, off);
}

double sh2000_comp_corrected(const struct sh2000_dsp *fw, unsigned int a)
{
	double off[SH2000_AXES];

	if (!fw->comp.has[0] && !fw->comp.has[1])
		return fw->ax[a].cmd;
	offsets_with(fw, a, fw->ax[a].cmd, off);
	return fw->ax[a].cmd + off[a];
}

/* The last cycle's corrections take the step the preset made in them
 * (axis a's own, and those of axes a cross table reads it for): the next
 * cycle's change of each is then what the motion made alone. */
void sh2000_comp_rebase(struct sh2000_dsp *fw, unsigned int a, double was)
{
	double now[SH2000_AXES], before[SH2000_AXES];
	unsigned int i;

	if (!fw->comp.has[0] && !fw->comp.has[1])
		return;
	offsets_with(fw, a, fw->ax[a].cmd, now);
	offsets_with(fw, a, was, before);
	for (i = 0; i < SH2000_AXES; i++)
		fw->comp.off[i] += now[i] - before[i];
}

/*
 * The correction is a function of the nominal position, so the nominal
 * set-point x whose corrected set-point x + off(x) is sp is found by
 * fixed-point iteration x = sp - off(x): it contracts by the table's
 * slope (a few 1e-5 for a scale, at most 0.02 for any table the check
 * against the axes' limits admits). It runs until a step moves x by
 * less than NOMINAL_DONE counts, far inside what the loop at rest takes
 * for a whole count (pid.c): a fixed four steps leave 0.02^4 of the first
 * guess' error, which would be 6e-5 count for a hold at a following
 * error of 20000 counts on the steepest table (its first guess 400
 * counts off); a gantry homing with 2000 ppm tables was left 5.8e-12
 * count off its count, now 1.2e-14. NOMINAL_STEPS bounds the work (at
 * 0.02 a step, 16 steps take an error of 1e9 counts below 1e-9).
 * The other axes stay at their nominal set-points.
 */
#define NOMINAL_STEPS	16
#define NOMINAL_DONE	1e-9

double sh2000_comp_nominal_at(const struct sh2000_dsp *fw, unsigned int a,
			      double sp)
{
	const struct sh2000_fw_comp *c = &fw->comp;
	double pos[SH2000_AXES], off[SH2000_AXES], was;
	unsigned int i;

	if (!c->has[0] && !c->has[1])
		return sp;
	for (i = 0; i < SH2000_AXES; i++)
		pos[i] = fw->ax[i].cmd;
	pos[a] = sp - c->off[a];
	for (i = 0; i < NOMINAL_STEPS; i++) {
		was = pos[a];
		offsets_at(c, pos, off);
		pos[a] = sp - off[a];
		if (fabs(pos[a] - was) <= NOMINAL_DONE)
			break;
	}
	return pos[a];
}

uint32_t sh2000_comp_nominal_counter(const struct sh2000_dsp *fw,
				     unsigned int a)
{
	int32_t o = (int32_t)lrint(fw->comp.off[a]);

	return (fw->ax[a].counter - (uint32_t)o) & SH2000_COUNTER_MASK;
}
