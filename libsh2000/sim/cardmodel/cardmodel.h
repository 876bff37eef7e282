/* SPDX-License-Identifier: MIT */
/*
 * The firmware's internal interface: the state of each part of the DSP's
 * program, fixed size, allocated before the first servo cycle. The
 * firmware reaches the card only through board.h (FPGA registers, the
 * dual-port RAM); the machine behind them is not visible from here.
 * Not installed, not used by the library: sh2000_cardsim.h is the API.
 */
#ifndef SH2000_CARDMODEL_H
#define SH2000_CARDMODEL_H

#include <math.h>
#include <stdint.h>

#include "sh2000/bspline.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000_hw.h"

#include "board.h"
#include "comp.h"

/* ---- interp.c: B-spline window ---- */

struct sh2000_interp {
	double w[SH2000_AXES][4];
};

void sh2000_interp_hold(struct sh2000_interp *ip, unsigned int axis, double x);
void sh2000_interp_push(struct sh2000_interp *ip, unsigned int axis, double x);
double sh2000_interp_last(const struct sh2000_interp *ip, unsigned int axis);
/* The window's jerk (constant over it), per s^3. */
double sh2000_interp_jerk(const struct sh2000_interp *ip, unsigned int axis,
			  double coarse_s);
/* Position, velocity (counts/s) and acceleration (counts/s^2) at t. */
void sh2000_interp_eval(const struct sh2000_interp *ip, unsigned int axis,
			double t, double coarse_s, double *x, double *v,
			double *a);

/* ---- pid.c: incremental PID + feed-forward, 16-bit DAC ---- */

struct sh2000_pid_gains {
	double kp, ti, td, kvff, kaff;
	int32_t dac_limit;
};

struct sh2000_pid {
	double u;		/* PID part u(k-1), clamped to the DAC limit */
	double e1, e2;		/* e(k-1), e(k-2) */
	/* this sample's terms (data gathering): P, I = u - P - D, D and the
	 * feed-forward, DAC codes */
	double p, i, d, ff;
	double carry;		/* the last code's rounding (the fine loop's) */
};

void sh2000_pid_reset(struct sh2000_pid *p);
/* One sample: error e (counts), feed-forward inputs v (counts/s) and a
 * (counts/s^2), sampling period tau (s). Returns the DAC code. */
int16_t sh2000_pid_step(struct sh2000_pid *p, const struct sh2000_pid_gains *g,
			double e, double v, double a, double tau);
/* The same on an error finer than a count (observer.c's): e as it is,
 * at rest too (sh2000_pid_step holds a set-point between two counts on
 * the count's edge, all a counter can say). */
int16_t sh2000_pid_step_fine(struct sh2000_pid *p,
			     const struct sh2000_pid_gains *g, double e,
			     double v, double a, double tau);

/* ---- observer.c: the position finer than a count ---- */

struct sh2000_obs {
	int on;			/* a model and an estimate */
	double x;		/* the reading, counts (counter + fraction) */
	double v;		/* the carriage's velocity, model counts/s */
	double dm;		/* the model's last step, counts */
	double sum_m;		/* the model's recent travel, counts */
	double rate;		/* the scale's counts per model count */
	/* exp(-alpha T) of the last step, kept while alpha T stays: one
	 * exp() per change, not per cycle (the VM suite's card model runs
	 * on an emulated CPU beside its host) */
	double at, decay;
};

/* ---- firmware.c: protocol v1 ---- */

struct sh2000_fw_params {
	double scale, kp, ti, td, kvff, kaff;
	int32_t dac_range, dac_limit, ferr_limit, soft_min, soft_max;
	double vmax, amax, home_vel;
	int32_t home_debounce, home_offset;
};

enum sh2000_home_phase {
	HOME_NONE = 0,
	HOME_BACKOFF,		/* started on the switch: leave it first */
	HOME_BACKSTOP,		/* off the switch: decelerate */
	HOME_SEEK,		/* towards the switch at HOME_VEL */
	HOME_STOP1,		/* switch confirmed: decelerate */
	HOME_CREEP,		/* towards the index at HOME_VEL / 10 */
	HOME_STOP2,		/* index latched: decelerate */
	HOME_RETURN,		/* back to the latched point */
};

/* index.c: the index latch armed by the host (protocol 1.6) */
struct sh2000_fw_index {
	uint16_t state;		/* enum sh2000_index_state */
	uint16_t arm;		/* +1 per INDEX_ARM */
	int64_t from;		/* the counter (extended) where it was armed */
	int64_t within;		/* counts it may travel, 0: no limit */
	uint32_t count;		/* the 28-bit counter at the mark */
	uint32_t cycle;		/* the servo cycle that found it */
};

struct sh2000_fw_axis {
	struct sh2000_fw_params prm;
	struct sh2000_pid pid;
	uint16_t state;		/* SH2000_AXIS_* */
	uint16_t faults;	/* SH2000_AXIS_FAULT_* */
	uint32_t counter;	/* last sampled 28-bit counter */
	int64_t act;		/* the counter, extended */
	int32_t delta;		/* counter change in this cycle */
	int limit;		/* switch bits this cycle: 1 -, 2 + */
	int index_seen;		/* the FPGA latched an index mark */
	uint32_t index_latch;	/* the counter at that mark */
	double cmd, cmd_v, cmd_a;	/* set-point and its derivatives */
	double cmd_j;		/* its jerk: the B-spline's, else 0 */
	double stop_a;		/* deceleration of a controlled stop */
	int16_t dac;
	struct sh2000_obs obs;	/* the reading finer than a count */
	double loop_e;		/* the error the PID closed on (counts) */
	unsigned int sat_cycles;
	/* a gantry side the skew fault held, braking to where it was held
	 * (gantry_loop.c's sh2000_gantry_brake_exempt): SKEW_BRAKE_*, the
	 * direction it moves in (-1, 0, 1), and how far (counts) beyond
	 * the held point its brake took it */
	int skew_brake;
	int brake_dir;
	double brake_peak_e;
	int prev_limit;		/* switch bits last cycle, for edges */
	/* a disabled axis: its position in the first record taken since the
	 * motion started or the axis was disabled (REJECT_DISABLED) */
	double rec_hold;
	int have_rec_hold;
	/* homing */
	enum sh2000_home_phase home;
	unsigned int home_flags;
	unsigned int debounce;
	double home_latch;	/* counter (extended) at the reference */
	struct sh2000_fw_index ix;
};

/* observer.c: forget the estimate (the axis disabled or enabled): the
 * next cycle starts from the middle of the count read. */
void sh2000_obs_reset(struct sh2000_obs *o);
/* At the cycle's start, the counter read: the estimate kept within its
 * count; returns the error the loop closes on for corrected set-point sp,
 * sp + 1/2 less the estimate (sp less the counter without a model: model
 * 0, or KVFF or KAFF 0). */
double sh2000_obs_error(struct sh2000_fw_axis *ax, double sp, int model,
			double T);
/* The DAC code chosen: the estimate moved over the period it holds. */
void sh2000_obs_predict(struct sh2000_fw_axis *ax, double T);

/* ---- gather.c: data gathering (protocol 1.2) ---- */

struct sh2000_dsp;

struct sh2000_gather_cfg {
	uint16_t mask[SH2000_AXES];	/* 1 << SH2000_GS_* per axis */
	uint32_t period, samples, pretrigger;
	uint16_t trigger;		/* enum sh2000_gather_trigger */
};

struct sh2000_gather {
	struct sh2000_gather_cfg cfg;	/* what GATHER_SET has set */
	struct sh2000_gather_cfg rec;	/* the record's, copied at ARM */
	uint16_t state;			/* enum sh2000_gather_state */
	uint16_t record;		/* +1 per ARM */
	uint32_t vps;			/* values per sample */
	uint32_t div;			/* cycles to the next sample */
	uint32_t pre_next, pre_count;	/* pre-trigger ring */
	uint32_t post;			/* samples from the trigger on */
	uint32_t trig_index, trig_cycle, first_cycle, last_cycle;
	uint16_t prev_faults;		/* trigger edges */
	int was_moving;
	uint32_t buf[SH2000_GATHER_BUFFER_VALUES];
};

void sh2000_gather_boot(struct sh2000_gather *g);
/* GATHER_* commands (seq: the CMD_SEQ being answered); SH2000_RES_*. */
uint16_t sh2000_gather_command(struct sh2000_dsp *fw, uint16_t seq,
			       uint16_t op, uint16_t axis, uint16_t param,
			       uint32_t arg, uint32_t *value);
/* End of every servo interrupt: trigger, sample. */
void sh2000_gather_cycle(struct sh2000_dsp *fw);

/* ---- gantry_loop.c: a gantry pair (protocol 1.7) ---- */

struct sh2000_gantry_loop {
	/* global parameters */
	int32_t pair;		/* GANTRY_PAIR: the two axes' mask, 0 none */
	double kp, ti, td;	/* the coupling loop */
	int32_t skew_limit;	/* counts */
	int32_t square;		/* counts: side b's switch - side a's */
	struct sh2000_pid pid;	/* the coupling loop's state */
	double skew;		/* this cycle's: e_a - e_b, counts */
	int squaring;		/* homing the pair: enum gantry_squaring */
	uint64_t sq_cycle;	/* the last HOMING cycle it was looked at */
	/* homing with the index: where each side started creeping towards
	 * its mark (the counter), how far it crept (counts, kept when it
	 * left the creep: its count is preset at home), whether it has */
	int64_t creep_from[2], creep_travel[2];
	int creeping[2];
};

enum gantry_squaring {
	GANTRY_SQ_NONE = 0,
	GANTRY_SQ_HOMING,	/* both sides on their own switches */
	GANTRY_SQ_MOVE,		/* side b to side a's position */
};

/* The pair's axes, a < b; 0 when there is none. */
int sh2000_gantry_axes(const struct sh2000_dsp *fw, unsigned int *a,
		       unsigned int *b);
/* A fault that disables axis: 1 and *other when the other side of its
 * pair must be disabled with it, else 0. */
int sh2000_gantry_partner(const struct sh2000_dsp *fw, unsigned int axis,
			  unsigned int *other);
enum { SKEW_BRAKE_NONE = 0, SKEW_BRAKE_STOPPING, SKEW_BRAKE_RETURNING };

/* Every servo cycle of an enabled axis with its following error e
 * (counts): 1 while the skew fault's hold lets it be beyond FERR_LIMIT,
 * braking to the held point; 0 when the check applies (one the beam
 * drags away from the held point faults). */
int sh2000_gantry_brake_exempt(struct sh2000_fw_axis *ax, double e);
/* GANTRY_PAIR set: the coupling loop starts from rest. */
void sh2000_gantry_paired(struct sh2000_dsp *fw);
/* After every axis' PID: the skew check and the coupling loop's share
 * of both sides' DAC codes. */
void sh2000_gantry_servo(struct sh2000_dsp *fw, double T);
/* HOME: an axis of the pair homes both; others home alone. */
uint16_t sh2000_gantry_home(struct sh2000_dsp *fw, unsigned int axis,
			    uint32_t flags);
/* While HOMING, after sh2000_home_cycle(): the pair's squaring. */
void sh2000_gantry_home_cycle(struct sh2000_dsp *fw, double T);

/* What the DSP's memory holds: the firmware's whole state. */
struct sh2000_dsp {
	struct sh2000_board *hw;	/* registers and RAM (board.h) */
	struct sh2000_fw_axis ax[SH2000_AXES];
	struct sh2000_interp ip;
	/* global parameters */
	int32_t coarse_us, fine_steps, host_timeout_ms, status_period;
	int32_t time_scale, time_ramp_ms;
	/* the time base (timebase.c): rate, its derivative, and each axis'
	 * set-point velocity and acceleration at full rate */
	double tb_sigma, tb_rate;
	double tb_v[SH2000_AXES], tb_a[SH2000_AXES];
	/* protocol state */
	unsigned int state;
	uint16_t faults;
	uint16_t heartbeat, estop_ack, tail, cmd_ack, snap_seq;
	uint16_t reject_count;
	int first_fault;	/* the first-fault record holds one (1.4) */
	uint16_t host_hb;
	uint64_t host_hb_cycles;	/* cycles since HOST_HEARTBEAT changed */
	double fine_t;		/* where in the coarse period, 0..1 */
	int need_point;		/* the next cycle starts a coarse period */
	uint64_t stop_left;	/* servo cycles left in a controlled stop */
	/* queue.c: the records received (ring and mailbox), POSTED */
	uint16_t posted;	/* records received */
	uint16_t head_seen;	/* HEAD as last seen */
	uint16_t mbox_seq;	/* MBOX_SEQ as last seen */
	int queue_bad;		/* a publication broke the ring's rules */
	int32_t ref[SH2000_AXES];	/* position of the last record received */
	uint8_t via[SH2000_RING_RECORDS];	/* enum sh2000_via of record n */
	int32_t mbox_pos[SH2000_RING_RECORDS][SH2000_AXES];
	uint16_t seg_seq;	/* SEQ of the last record consumed */
	int have_seq;		/* seg_seq belongs to this motion */
	unsigned int pad_left;	/* END padding periods still to run */
	int ending;		/* END record seen */
	unsigned int status_div;
	uint64_t cycle;		/* servo interrupts taken */
	struct sh2000_gather gather;	/* its record lives here */
	struct sh2000_fw_comp comp;	/* compensation tables (comp.c) */
	struct sh2000_gantry_loop gantry;	/* protocol 1.7 */
};

static inline int sh2000_axis_enabled(const struct sh2000_fw_axis *ax)
{
	return (ax->state & SH2000_AXIS_ENABLED) != 0;
}

/* Axis a's following error as its loop closes it: the set-point with the
 * compensation tables' correction, less the counter (the PID's error,
 * gathered FERR, the gantry's skew; docs/protocol.md 18.3). */
static inline double sh2000_fw_ferr(const struct sh2000_dsp *fw,
				    unsigned int a)
{
	return fw->ax[a].cmd + fw->comp.off[a] - (double)fw->ax[a].act;
}

/* The set-point as the host sees it (snapshot CMD, gathered SETPOINT):
 * rounded to a count, within int32. */
static inline int32_t sh2000_fw_cmd_counts(const struct sh2000_fw_axis *ax)
{
	double c = nearbyint(ax->cmd);

	if (c > 2147483647.0)
		c = 2147483647.0;
	if (c < -2147483648.0)
		c = -2147483648.0;
	return (int32_t)c;
}

/* The firmware is moving: the protocol's one definition of it. */
static inline int sh2000_fw_in_motion(const struct sh2000_dsp *fw)
{
	return sh2000_state_moving(fw->state);
}

/* queue.c: how record n reached the card */
enum sh2000_via {
	SH2000_VIA_RING = 0,		/* in its ring slot */
	SH2000_VIA_MBOX = 1,		/* posted, copied to mbox_pos */
	SH2000_VIA_MBOX_LOST = 2,	/* posted with the next number: the
					 * post before it was lost */
	SH2000_VIA_MBOX_BAD = 3,	/* posted with a wrong check word */
};

/* POSTED and TAIL from what the host left (at boot). */
void sh2000_queue_boot(struct sh2000_dsp *fw);
/* Take what the host published since the last call: a post, then ring
 * records (HEAD). A publication beyond the queue's room is counted and
 * sets queue_bad (the caller latches FAULT_PROTOCOL). */
void sh2000_queue_receive(struct sh2000_dsp *fw);
uint16_t sh2000_queue_fill(const struct sh2000_dsp *fw);
/* Everything published is discarded: TAIL := POSTED. */
void sh2000_queue_discard(struct sh2000_dsp *fw);
/* Record TAIL in the ring's layout; TAIL += 1. Returns enum sh2000_via;
 * *num is the record's number. */
unsigned int sh2000_queue_take(struct sh2000_dsp *fw,
			       uint16_t rec[SH2000_RECORD_WORDS], uint16_t *num);
/* SEQ of record TAIL (not consumed). */
uint16_t sh2000_queue_first_seq(struct sh2000_dsp *fw);

/* timebase.c: the rate of this servo cycle (fw->tb_sigma, fw->tb_rate) */
void sh2000_tb_step(struct sh2000_dsp *fw, double T);

/* firmware.c */
/* Power-up on a board: parameters, RAM words, the magic last. */
void sh2000_dsp_boot(struct sh2000_dsp *fw, struct sh2000_board *hw);
/* One servo interrupt (protocol v1's cycle); the DAC outputs are then
 * held until the next. */
void sh2000_dsp_interrupt(struct sh2000_dsp *fw);
uint64_t sh2000_dsp_servo_period_ns(const struct sh2000_dsp *fw);
void sh2000_fw_publish_words(struct sh2000_dsp *fw);
double sh2000_fw_servo_s(const struct sh2000_dsp *fw);
/* Set-point of axis a becomes x, at rest; the window holds x. */
void sh2000_fw_hold_at(struct sh2000_dsp *fw, unsigned int a, double x);
/* Axis a holds where its carriage is (its corrected set-point at the
 * counter), at rest: the stops, disable, enable and RESET. */
void sh2000_fw_hold_here(struct sh2000_dsp *fw, unsigned int a);
/* A card fault (SH2000_FAULT_*) latched: the card stops (controlled). */
void sh2000_fw_card_fault(struct sh2000_dsp *fw, uint16_t bit);
/* The FPGA counter preset: the axis reads `pos` here from now on. */
void sh2000_fw_set_position(struct sh2000_dsp *fw, unsigned int a, int64_t pos);

/* latch.c: every fault the firmware latches: axis 0..3 and an
 * SH2000_AXIS_FAULT_* bit, or SH2000_AXIS_GLOBAL and an SH2000_FAULT_*
 * bit; the first since RESET also goes into the first-fault record. */
void sh2000_fw_latch(struct sh2000_dsp *fw, unsigned int axis, uint16_t bit);
/* RESET and boot: no first fault. */
void sh2000_fw_first_fault_clear(struct sh2000_dsp *fw);

/* params.c: results are SH2000_RES_* */
uint16_t sh2000_fw_get_param(struct sh2000_dsp *fw, unsigned int axis,
			    unsigned int id, uint32_t *out);
uint16_t sh2000_fw_set_param(struct sh2000_dsp *fw, unsigned int axis,
			    unsigned int id, uint32_t bits);
void sh2000_fw_default_params(struct sh2000_dsp *fw);

/* homing.c */
/* What the two commands that take an axis' index latch (HOME, INDEX_ARM)
 * check first, in this order: the axis (BAD_AXIS), bad_value (BAD_VALUE:
 * the caller's check of its flags), a latched fault (FAULTED), the axis
 * enabled (DISABLED); SH2000_RES_OK if all pass. */
uint16_t sh2000_latch_cmd_check(const struct sh2000_dsp *fw,
				unsigned int axis, int bad_value);
uint16_t sh2000_home_start(struct sh2000_dsp *fw, unsigned int axis,
			   uint32_t flags);
void sh2000_home_cycle(struct sh2000_dsp *fw, double T);
void sh2000_home_abort(struct sh2000_fw_axis *ax);
/* The set-point towards target within AMAX and |v| <= vcap; 1 when
 * there (the gantry's squaring move). */
int sh2000_home_move_to(struct sh2000_fw_axis *ax, double target,
			double vcap, double T);
/* Axis a's counter preset by delta at rest (a homing's reference, the
 * gantry's squaring): the corrected set-point moves with it, no more, and
 * the nominal set-point is the one whose correction is there (the
 * compensation tables'; without them it moves by delta too). */
void sh2000_home_preset(struct sh2000_dsp *fw, unsigned int a, int64_t delta);

/* index.c: INDEX_ARM (value: the arm's number) and INDEX_DISARM; results
 * SH2000_RES_*. sh2000_fw_index_cycle runs for each axis every cycle once
 * its inputs are sampled. */
uint16_t sh2000_fw_index_arm(struct sh2000_dsp *fw, unsigned int axis,
			  uint16_t flags, uint32_t within, uint32_t *value);
uint16_t sh2000_fw_index_disarm(struct sh2000_dsp *fw, unsigned int axis);
void sh2000_fw_index_cycle(struct sh2000_dsp *fw, unsigned int a);
/* Power-up: every block OFF, every latch in its default mode. */
void sh2000_fw_index_boot(struct sh2000_dsp *fw);

#endif /* SH2000_CARDMODEL_H */
