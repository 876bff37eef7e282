// SPDX-License-Identifier: MIT
/*
 * The board: the FPGA (encoder counters with their 28-bit wrap, index
 * latches, switch inputs; the host side's address counter in
 * sh2000_fpga.h), the DAC7744, the dual-port RAM, the oscillator, and the
 * machine behind them (one plant per axis). The firmware reaches it only
 * through board.h; faults are injected here, in the hardware, so that the
 * firmware meets them the way it would meet the real ones.
 */
#include <math.h>
#include <stdlib.h>

#include "board_sim.h"
#include "gantry.h"
#include "sh2000/sh2000_protocol.h"

struct board_axis {
	struct sh2000_plant plant;
	int64_t offset;		/* counter = scale + offset, wrapped */
	uint32_t latch;		/* index latch */
	int latched;		/* HWIN_INDEX */
	uint32_t index_mode;	/* SH2000_HWIDX_* */
	int16_t dac;		/* DAC7744 output code */
	unsigned int range;	/* enum sh2000_dac_range */
	unsigned int forced;	/* injected: limit inputs forced, bit0 -, bit1 + */
};

/* SH2000_INJECT_DROP_SEGMENT: the one place the board knows the
 * protocol's ring (where records live, the TAIL word), as the injector
 * must to lose one record's write. */
struct record_drop {
	int armed;
	uint16_t record;	/* number of the record whose write is lost */
	uint16_t stale[SH2000_RECORD_WORDS];	/* what its slot held */
};

struct sh2000_board {
	uint16_t *ram;
	struct sh2000_fpga host;
	struct board_axis ax[SH2000_AXES];
	double ppm;		/* oscillator error */
	double carry_ns;	/* host-time fraction not yet handed out */
	int stuck;		/* RAM word the DSP cannot write, or -1 */
	struct record_drop drop;
	struct sh2000_geometry geom;	/* the machine's (the plants') */
	struct sh2000_gantry gantry;	/* two axes on one beam, if on */
};

static uint32_t wrap(int64_t c)
{
	return (uint32_t)((uint64_t)c & SH2000_COUNTER_MASK);
}

int sh2000_board_create(struct sh2000_board **out, uint16_t *ram,
			const struct sh2000_sim_config *cfg)
{
	struct sh2000_board *b;
	unsigned int a;

	if (!out || !ram || !cfg)
		return -22;
	b = calloc(1, sizeof(*b));
	if (!b)
		return -12;
	b->ram = ram;
	sh2000_geometry_none(&b->geom);
	sh2000_fpga_init(&b->host, ram);
	b->stuck = -1;
	for (a = 0; a < SH2000_AXES; a++) {
		struct board_axis *x = &b->ax[a];

		sh2000_plant_init(&x->plant, &cfg->axis[a]);
		sh2000_plant_set_geometry(&x->plant, &b->geom, a);
		/* an incremental scale: the counter powers up at 0 */
		x->offset = -sh2000_plant_scale(&x->plant);
		x->range = SH2000_DAC_PM10V;
	}
	*out = b;
	return 0;
}

void sh2000_board_destroy(struct sh2000_board *b)
{
	free(b);
}

/* ---- the firmware's view (board.h) ---- */

static uint32_t inputs(const struct board_axis *x)
{
	uint32_t in = 0;

	if (x->latched)
		in |= SH2000_HWIN_INDEX;
	if ((x->forced & 1u) || sh2000_plant_limit_neg(&x->plant))
		in |= SH2000_HWIN_LIMIT_NEG;
	if ((x->forced & 2u) || sh2000_plant_limit_pos(&x->plant))
		in |= SH2000_HWIN_LIMIT_POS;
	if (sh2000_plant_home(&x->plant))
		in |= SH2000_HWIN_HOME;
	return in;
}

uint32_t sh2000_board_read(struct sh2000_board *b, unsigned int axis,
			   unsigned int reg)
{
	const struct board_axis *x;

	if (axis >= SH2000_AXES)
		return 0;
	x = &b->ax[axis];
	switch (reg) {
	case SH2000_HWREG_COUNTER:
		return wrap(sh2000_plant_scale(&x->plant) + x->offset);
	case SH2000_HWREG_INPUTS:
		return inputs(x);
	case SH2000_HWREG_INDEX_LATCH:
		return x->latch;
	case SH2000_HWREG_DAC:
		return (uint16_t)x->dac;
	case SH2000_HWREG_DAC_RANGE:
		return x->range;
	case SH2000_HWREG_INDEX_MODE:
		return x->index_mode;
	default:	/* write-only or not decoded */
		return 0;
	}
}

void sh2000_board_write(struct sh2000_board *b, unsigned int axis,
			unsigned int reg, uint32_t v)
{
	struct board_axis *x;

	if (axis >= SH2000_AXES)
		return;
	x = &b->ax[axis];
	switch (reg) {
	case SH2000_HWREG_PRESET:
		x->offset = (int64_t)(v & SH2000_COUNTER_MASK) -
			    sh2000_plant_scale(&x->plant);
		break;
	case SH2000_HWREG_INDEX_ARM:
		x->latched = 0;
		break;
	case SH2000_HWREG_DAC:
		x->dac = (int16_t)(uint16_t)v;
		break;
	case SH2000_HWREG_DAC_RANGE:
		if (v <= SH2000_DAC_PM10V)
			x->range = v;
		break;
	case SH2000_HWREG_INDEX_MODE:
		x->index_mode = v & SH2000_HWIDX_ALL;
		break;
	default:	/* read-only or not decoded */
		break;
	}
}

/* The record whose write was lost: its slot is read for the first time,
 * so the RAM shows what it would have held without the write. */
static void apply_drop(struct sh2000_board *b, unsigned int w)
{
	unsigned int base = SH2000_W_RING_BASE +
			    (b->drop.record % SH2000_RING_RECORDS) *
				    SH2000_RECORD_WORDS, i;

	if (w < base || w >= base + SH2000_RECORD_WORDS ||
	    sh2000_dpram_read(b->ram, SH2000_W_TAIL) != b->drop.record)
		return;
	for (i = 0; i < SH2000_RECORD_WORDS; i++)
		sh2000_dpram_write(b->ram, base + i, b->drop.stale[i]);
	b->drop.armed = 0;
}

uint16_t sh2000_board_ram_read(struct sh2000_board *b, unsigned int w)
{
	if (b->drop.armed)
		apply_drop(b, w);
	return sh2000_dpram_read(b->ram, w);
}

void sh2000_board_ram_write(struct sh2000_board *b, unsigned int w,
			    uint16_t v)
{
	if ((int)w == b->stuck)
		return;
	sh2000_dpram_write(b->ram, w, v);
}

/* ---- running the machine ---- */

/* DAC7744 volts per code for a range (unipolar ranges: the amplifier
 * takes mid-scale as 0 V, docs/cardmodel.md). */
static double volts_per_code(unsigned int range)
{
	switch (range) {
	case SH2000_DAC_0_5V:
		return 5.0 / 65536.0;
	case SH2000_DAC_0_10V:
		return 10.0 / 65536.0;
	case SH2000_DAC_PM5V:
		return 5.0 / 32768.0;
	default:
		return 10.0 / 32768.0;
	}
}

/* The index latch: the first edge of the mode's kind after ARM, where the
 * mask input (the home switch) lets it through; later ones wait. */
static void index_latch(struct board_axis *x)
{
	const struct sh2000_index_edge *e =
		(x->index_mode & SH2000_HWIDX_FALLING) ? &x->plant.fall :
							 &x->plant.rise;
	int want = !(x->index_mode & SH2000_HWIDX_MASK_INV);

	if (x->latched || !e->crossed)
		return;
	if ((x->index_mode & SH2000_HWIDX_MASK) && e->home != want)
		return;
	x->latch = wrap(e->mark + x->offset);
	x->latched = 1;
}

static uint64_t host_ns(struct sh2000_board *b, uint64_t card_ns)
{
	double t = (double)card_ns * b->ppm * 1e-6 + b->carry_ns;
	double whole = floor(t);

	b->carry_ns = t - whole;
	return (uint64_t)((int64_t)card_ns + (int64_t)whole);
}

static double volts(const struct board_axis *x)
{
	return x->dac * volts_per_code(x->range);
}

/* The beam's two sides move together, the carriage where it was at the
 * start of the period (it moves some um in one). */
static void step_gantry(struct sh2000_board *b, double T)
{
	const struct sh2000_gantry_config *g = &b->gantry.cfg;
	struct board_axis *xa = &b->ax[g->side_a], *xb = &b->ax[g->side_b];

	sh2000_gantry_step(&b->gantry, &xa->plant, &xb->plant,
			   g->carriage_axis >= 0 ?
				   &b->ax[g->carriage_axis].plant : NULL,
			   volts(xa), volts(xb), T);
}

uint64_t sh2000_board_run(struct sh2000_board *b, uint64_t card_ns)
{
	uint64_t ns = host_ns(b, card_ns);
	double T = (double)ns * 1e-9;
	unsigned int a;

	if (b->gantry.on)
		step_gantry(b, T);
	for (a = 0; a < SH2000_AXES; a++) {
		struct board_axis *x = &b->ax[a];

		if (!sh2000_gantry_side(&b->gantry, a))
			sh2000_plant_step(&x->plant, volts(x), T);
		index_latch(x);
	}
	return ns;
}

int sh2000_board_set_clock_ppm(struct sh2000_board *b, double ppm)
{
	if (!(fabs(ppm) <= SH2000_BOARD_PPM_MAX))
		return -22;
	b->ppm = ppm;
	return 0;
}

double sh2000_board_clock_ppm(const struct sh2000_board *b)
{
	return b->ppm;
}

struct sh2000_fpga *sh2000_board_host(struct sh2000_board *b)
{
	return &b->host;
}

uint16_t *sh2000_board_ram(struct sh2000_board *b)
{
	return b->ram;
}

const struct sh2000_plant *sh2000_board_plant(const struct sh2000_board *b,
					      unsigned int axis)
{
	return axis < SH2000_AXES ? &b->ax[axis].plant : NULL;
}

int sh2000_board_set_geometry(struct sh2000_board *b,
			       const struct sh2000_geometry *g)
{
	int64_t before[SH2000_AXES];
	unsigned int a, k;

	if (g) {
		for (a = 0; a < SH2000_AXES; a++)
			for (k = 0; k < SH2000_PITCH_TERMS; k++)
				if (!(g->pitch_period_mm[a][k] > 0.0))
					return -22;
		if (!(g->travel_hi_mm != g->travel_lo_mm))
			return -22;
	}
	for (a = 0; a < SH2000_AXES; a++)
		before[a] = sh2000_plant_scale(&b->ax[a].plant);
	if (g)
		b->geom = *g;
	else
		sh2000_geometry_none(&b->geom);
	/* the counter goes on from where it was */
	for (a = 0; a < SH2000_AXES; a++)
		b->ax[a].offset += before[a] - sh2000_plant_scale(&b->ax[a].plant);
	return 0;
}

void sh2000_board_tool(const struct sh2000_board *b, double tool[SH2000_AXES])
{
	double x[SH2000_AXES];
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		x[a] = b->ax[a].plant.x_mm;
	sh2000_geometry_tool(&b->geom, x, tool);
}

int sh2000_board_set_gantry(struct sh2000_board *b,
			    const struct sh2000_gantry_config *g)
{
	if (!g) {
		b->gantry.on = 0;
		return 0;
	}
	if (sh2000_gantry_check(g))
		return -22;
	b->gantry.cfg = *g;
	b->gantry.on = 1;
	return 0;
}

double sh2000_board_gantry_yaw_mm(const struct sh2000_board *b)
{
	const struct sh2000_gantry_config *g = &b->gantry.cfg;

	if (!b->gantry.on)
		return 0.0;
	return b->ax[g->side_a].plant.x_mm - b->ax[g->side_b].plant.x_mm;
}

/* ---- injected faults ---- */

int sh2000_board_jam(struct sh2000_board *b, unsigned int axis, int on)
{
	if (axis >= SH2000_AXES)
		return -22;
	b->ax[axis].plant.jammed = on != 0;
	return 0;
}

int sh2000_board_force_limit(struct sh2000_board *b, unsigned int axis,
			     unsigned int bits)
{
	if (axis >= SH2000_AXES)
		return -22;
	b->ax[axis].forced |= bits & 3u;
	return 0;
}

int sh2000_board_glitch(struct sh2000_board *b, unsigned int axis,
			int32_t counts)
{
	if (axis >= SH2000_AXES)
		return -22;
	b->ax[axis].offset += counts;
	return 0;
}

int sh2000_board_flip(struct sh2000_board *b, unsigned int w, uint16_t mask)
{
	if (w >= SH2000_RAM_WORDS)
		return -22;
	sh2000_dpram_write(b->ram, w,
			   (uint16_t)(sh2000_dpram_read(b->ram, w) ^ mask));
	return 0;
}

int sh2000_board_stick(struct sh2000_board *b, unsigned int w)
{
	if (w >= SH2000_RAM_WORDS)
		return -22;
	b->stuck = (int)w;
	return 0;
}

void sh2000_board_drop_record(struct sh2000_board *b)
{
	uint16_t head = sh2000_dpram_read(b->ram, SH2000_W_HEAD);
	unsigned int base = SH2000_W_RING_BASE +
			    (head % SH2000_RING_RECORDS) * SH2000_RECORD_WORDS,
		     i;

	for (i = 0; i < SH2000_RECORD_WORDS; i++)
		b->drop.stale[i] = sh2000_dpram_read(b->ram, base + i);
	b->drop.record = head;
	b->drop.armed = 1;
}

void sh2000_board_clear_faults(struct sh2000_board *b)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		b->ax[a].plant.jammed = 0;
		b->ax[a].forced = 0;
	}
	b->stuck = -1;
	b->drop.armed = 0;
}
