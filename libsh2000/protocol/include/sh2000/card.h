/* SPDX-License-Identifier: MIT */
/*
 * What the card is, as every host program sees it: four axes, the card's
 * states and fault bits, why a record is rejected, the commands and their
 * results, and the parameters (ids, names, types, ranges, defaults).
 *
 * This is the part of protocol v1 that the device API (sh2000.h) speaks in.
 * Where the words live in the dual-port RAM is not here: that is
 * sh2000_protocol.h, which the library, the card model and firmware writers
 * include, and which an application never needs.
 */
#ifndef SH2000_CARD_H
#define SH2000_CARD_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SH2000_PROTO_MAJOR		1u
#define SH2000_PROTO_MINOR		7u
#define SH2000_PROTO_VERSION		((SH2000_PROTO_MAJOR << 8) | SH2000_PROTO_MINOR)
#define SH2000_PROTO_VERSION_MAJOR(v)	(((v) >> 8) & 0xffu)
#define SH2000_PROTO_VERSION_MINOR(v)	((v) & 0xffu)
/* The minor version that brought a feature: a host checks the card's. */
#define SH2000_PROTO_MINOR_TIME_BASE	1u	/* time_scale, time_ramp_ms */
#define SH2000_PROTO_MINOR_GATHER	2u	/* data gathering (GATHER_*) */
#define SH2000_PROTO_MINOR_MAILBOX	3u	/* POSTED and the point mailbox */
#define SH2000_PROTO_MINOR_FIRST_FAULT	4u	/* the first-fault record (FF_*) */
#define SH2000_PROTO_MINOR_COMP		5u	/* compensation tables (COMP_*) */
#define SH2000_PROTO_MINOR_INDEX	6u	/* INDEX_ARM while a stream runs,
						 * the index block (IX_*) */
#define SH2000_PROTO_MINOR_GANTRY	7u	/* gantry_* parameters, AXIS_FAULT_SKEW */

/* The one definition of the axis count, and of the axes' names (index:
 * axis; the G-code words that move them; tools print them lower case). */
#define SH2000_AXES			4u
#define SH2000_AXIS_LETTERS		"XYZA"

/* ---------------------------------------------------------------------------
 * Card state and faults.
 * ------------------------------------------------------------------------ */

enum sh2000_card_state {
	SH2000_STATE_BOOT = 0,		/* firmware not running yet */
	SH2000_STATE_IDLE = 1,		/* holding; ring empty */
	SH2000_STATE_RUNNING = 2,	/* consuming segment records */
	SH2000_STATE_STOPPING = 3,	/* controlled deceleration */
	SH2000_STATE_HOMING = 4,	/* at least one axis homing */
	SH2000_STATE_FAULT = 5,		/* a fault is latched; reset clears */
	SH2000_STATE_ESTOP = 6,		/* emergency stop latched; reset clears */
};

/* Card faults (SH2000_W_FAULTS), latched until SH2000_CMD_RESET. */
#define SH2000_FAULT_UNDERRUN		0x0001u	/* ring ran dry mid-motion */
#define SH2000_FAULT_HOST_TIMEOUT	0x0002u	/* host heartbeat stopped */
#define SH2000_FAULT_ESTOP		0x0004u	/* emergency stop */
#define SH2000_FAULT_REJECTED		0x0008u	/* a segment was rejected */
#define SH2000_FAULT_PROTOCOL		0x0010u	/* impossible ring fill */
#define SH2000_FAULT_AXIS		0x0020u	/* an axis has a fault */

/* Axis faults (SH2000_W_AXIS_FAULTS), latched until SH2000_CMD_RESET. */
#define SH2000_AXIS_FAULT_FERR		0x0001u	/* following error limit */
#define SH2000_AXIS_FAULT_SOFT_LIMIT	0x0002u	/* set-point beyond a soft limit */
#define SH2000_AXIS_FAULT_HARD_LIMIT	0x0004u	/* limit switch hit */
#define SH2000_AXIS_FAULT_DAC_SAT	0x0008u	/* DAC saturated too long */
#define SH2000_AXIS_FAULT_COUNTER	0x0010u	/* implausible counter jump */
#define SH2000_AXIS_FAULT_HOME		0x0020u	/* homing failed */
/* protocol 1.7: the gantry pair's skew beyond gantry_skew_limit (both
 * sides latch it) */
#define SH2000_AXIS_FAULT_SKEW		0x0040u

/* Axis state bits (SH2000_W_AXIS_STATE), live. */
#define SH2000_AXIS_ENABLED		0x0001u
#define SH2000_AXIS_HOMED		0x0002u
#define SH2000_AXIS_HOMING		0x0004u
#define SH2000_AXIS_MOVING		0x0008u
#define SH2000_AXIS_LIMIT_POS		0x0010u	/* + limit switch active */
#define SH2000_AXIS_LIMIT_NEG		0x0020u	/* - limit switch active */
#define SH2000_AXIS_HOME_SW		0x0040u	/* home switch active */
#define SH2000_AXIS_INDEX		0x0080u	/* index seen since homing */
/* protocol 1.6 (INDEX_ARM): the axis' index latch is armed; the last arm
 * latched a mark (the index block holds where and when). Neither after an
 * arm: it ended without a mark (the block's IX_STATE says why). */
#define SH2000_AXIS_INDEX_ARMED		0x0100u
#define SH2000_AXIS_INDEX_LATCHED	0x0200u

/* Why a record was rejected (SH2000_W_REJECT_REASON). */
enum sh2000_reject_reason {
	SH2000_REJECT_NONE = 0,
	SH2000_REJECT_CHECKSUM = 1,	/* record check word wrong */
	SH2000_REJECT_RESERVED = 2,	/* reserved word or flag bit set */
	SH2000_REJECT_VELOCITY = 3,	/* step exceeds an axis' max velocity */
	SH2000_REJECT_SOFT_LIMIT = 4,	/* point beyond a soft limit */
	SH2000_REJECT_DISABLED = 5,	/* moves an axis that is not enabled */
	SH2000_REJECT_STATE = 6,	/* card not in a state to move */
	/* v1.0 addition: a record was lost before it reached the RAM: within
	 * a motion its successor's SEQ is not the previous + 1 (the card
	 * model's SH2000_INJECT_DROP_SEGMENT loses the write). REJECT_SEQ is
	 * the lost record's number. Handled like any rejection. */
	SH2000_REJECT_DROPPED = 7,
};

/* ---------------------------------------------------------------------------
 * Commands (the single-axis controller paper [R4]'s CNC/RSP): one at a time, each acknowledged.
 * ------------------------------------------------------------------------ */

enum sh2000_cmd_op {
	SH2000_CMD_NOP = 0,		/* ping */
	SH2000_CMD_ENABLE = 1,		/* ARG = axis mask */
	SH2000_CMD_DISABLE = 2,		/* ARG = axis mask */
	SH2000_CMD_SET_PARAM = 3,	/* AXIS, PARAM, ARG = value */
	SH2000_CMD_GET_PARAM = 4,	/* AXIS, PARAM -> VALUE */
	SH2000_CMD_HOME = 5,		/* AXIS, ARG = SH2000_HOME_F_* */
	SH2000_CMD_STOP = 6,		/* controlled stop, ring discarded */
	SH2000_CMD_RESET = 7,		/* clear latched faults, go idle */
	SH2000_CMD_SET_POSITION = 8,	/* AXIS, ARG = new position (counts) */
	/* protocol 1.2: data gathering (docs/protocol.md section 17); a
	 * range of their own, 16.., so that other additions keep 9.. */
	SH2000_CMD_GATHER_SET = 16,	/* AXIS, PARAM = field, ARG = value */
	SH2000_CMD_GATHER_ARM = 17,	/* start a record -> VALUE = number */
	SH2000_CMD_GATHER_STOP = 18,	/* end the record now */
	SH2000_CMD_GATHER_INFO = 19,	/* describe it in the window */
	SH2000_CMD_GATHER_READ = 20,	/* ARG = first value -> window */
	/* protocol 1.5: compensation tables (docs/protocol.md section 18),
	 * a range of their own, 24.. */
	SH2000_CMD_COMP_BEGIN = 24,	/* ARG = image words: staging emptied */
	SH2000_CMD_COMP_PAGE = 25,	/* ARG = first word, PARAM = count;
					 * the words in the page window */
	SH2000_CMD_COMP_COMMIT = 26,	/* ARG = the image's sh2000_comp_sum():
					 * check, then switch at rest ->
					 * VALUE = refusal (SH2000_COMP_FAULT) */
	SH2000_CMD_COMP_CLEAR = 27,	/* no tables (at rest) */
	/* protocol 1.6: the index latch while a stream runs (docs/protocol.md
	 * section 13.1), after the compensation commands */
	SH2000_CMD_INDEX_ARM = 28,	/* AXIS, PARAM = SH2000_INDEX_F_*, ARG =
					 * counts it may travel without a
					 * mark (0: no limit) -> VALUE = the
					 * arm's number (IX_ARM) */
	SH2000_CMD_INDEX_DISARM = 29,	/* AXIS */
};

/* SH2000_W_CMD_AXIS value addressing a global parameter. */
#define SH2000_AXIS_GLOBAL		0xffffu

/* HOME flags */
#define SH2000_HOME_F_INDEX		0x0001u	/* finish on the encoder index */

/* INDEX_ARM flags (CMD_PARAM), as hostmot2's encoder names them:
 * MASK (index-mask): only a mark seen while the home switch is active
 * counts (the switch is the latch's mask input); MASK_INVERT
 * (index-mask-invert, with MASK): only one seen while it is inactive;
 * RISING (index-invert): the latch takes the edge where the mark's
 * signal rises (the carriage enters the mark), else where it falls
 * (leaves it). A mark of no width rises and falls at one count. */
#define SH2000_INDEX_F_MASK		0x0001u
#define SH2000_INDEX_F_MASK_INVERT	0x0002u
#define SH2000_INDEX_F_RISING		0x0004u
#define SH2000_INDEX_F_ALL		0x0007u

/* IX_STATE of an axis' index block: what became of the last INDEX_ARM. */
enum sh2000_index_state {
	SH2000_INDEX_OFF = 0,		/* never armed, or disarmed */
	SH2000_INDEX_ARMED = 1,		/* waiting for a mark */
	SH2000_INDEX_LATCHED = 2,	/* a mark: IX_COUNT, IX_CYCLE */
	SH2000_INDEX_MISSED = 3,	/* travelled the arm's limit, no mark */
	SH2000_INDEX_ABORTED = 4,	/* the axis was disabled, or a fault or
					 * emergency stop latched, while armed */
};

/* SH2000_W_CMD_RESULT */
enum sh2000_cmd_result {
	SH2000_RES_OK = 0,
	SH2000_RES_BAD_OP = 1,
	SH2000_RES_BAD_AXIS = 2,
	SH2000_RES_BAD_PARAM = 3,
	SH2000_RES_BAD_VALUE = 4,	/* out of range or not representable */
	SH2000_RES_BUSY = 5,		/* not allowed while moving */
	SH2000_RES_FAULTED = 6,		/* a latched fault forbids it */
	SH2000_RES_CHECKSUM = 7,	/* CMD_CHECK wrong: nothing done */
	SH2000_RES_DISABLED = 8,	/* HOME/SET_POSITION needs an enabled
					 * (HOME) or idle axis (v1.0 addition) */
};

/* ---------------------------------------------------------------------------
 * Parameters. Per-axis parameters use AXIS 0..3, global ones AXIS_GLOBAL.
 * F32 values are IEEE-754 binary32 bit patterns (the firmware converts to
 * the C3x float format), I32 values two's complement. Units are the card's:
 * counts, seconds, DAC codes.
 * ------------------------------------------------------------------------ */

enum sh2000_param {
	/* per axis */
	SH2000_P_SCALE = 0,		/* F32 counts per mm, > 0 */
	SH2000_P_KP = 1,		/* F32 DAC codes per count, >= 0 */
	SH2000_P_TI = 2,		/* F32 integral time s, 0 = none */
	SH2000_P_TD = 3,		/* F32 derivative time s, >= 0 */
	SH2000_P_KVFF = 4,		/* F32 DAC codes per count/s, >= 0 */
	SH2000_P_KAFF = 5,		/* F32 DAC codes per count/s^2, >= 0 */
	SH2000_P_DAC_RANGE = 6,		/* I32 enum sh2000_dac_range */
	SH2000_P_DAC_LIMIT = 7,		/* I32 max |DAC code|, 1..32767 */
	SH2000_P_FERR_LIMIT = 8,	/* I32 counts, > 0 */
	SH2000_P_SOFT_MIN = 9,		/* I32 counts, < SOFT_MAX */
	SH2000_P_SOFT_MAX = 10,		/* I32 counts */
	SH2000_P_VMAX = 11,		/* F32 counts/s, > 0 */
	SH2000_P_AMAX = 12,		/* F32 counts/s^2, > 0 */
	SH2000_P_HOME_VEL = 13,		/* F32 counts/s, sign = direction, != 0 */
	SH2000_P_HOME_DEBOUNCE = 14,	/* I32 servo cycles, 1..1000 */
	SH2000_P_HOME_OFFSET = 15,	/* I32 counts given to the home point */
	SH2000_AXIS_PARAMS = 16,
	/* global */
	SH2000_GP_COARSE_PERIOD_US = 32,	/* I32 us, 100..100000 */
	SH2000_GP_FINE_STEPS = 33,		/* I32 servo cycles per coarse, 1..1000 */
	SH2000_GP_HOST_TIMEOUT_MS = 34,		/* I32 ms, 0 = off, <= 60000 */
	SH2000_GP_STATUS_PERIOD = 35,		/* I32 servo cycles, 1..1000 */
	/* protocol 1.1: the card's time base (docs/protocol.md 8.4) */
	SH2000_GP_TIME_SCALE = 36,		/* I32 0..SH2000_TIME_SCALE_FULL */
	SH2000_GP_TIME_RAMP_MS = 37,		/* I32 ms for a 0..1 ramp, 1..60000 */
	/* protocol 1.7: a gantry pair (docs/protocol.md "Gantry pairs") */
	SH2000_GP_GANTRY_PAIR = 38,		/* I32 axis mask: 0 or two bits */
	SH2000_GP_GANTRY_KP = 39,		/* F32 DAC codes per count of skew */
	SH2000_GP_GANTRY_TI = 40,		/* F32 integral time s, 0 = none */
	SH2000_GP_GANTRY_TD = 41,		/* F32 derivative time s */
	SH2000_GP_GANTRY_SKEW_LIMIT = 42,	/* I32 counts, > 0 */
	SH2000_GP_GANTRY_SQUARE = 43,		/* I32 counts: b's switch - a's */
	SH2000_GP_FIRST = SH2000_GP_COARSE_PERIOD_US,
	SH2000_GP_END = 44,
};

/* TIME_SCALE at full rate: the rate is TIME_SCALE / FULL (0.01 % steps). */
#define SH2000_TIME_SCALE_FULL	10000

enum sh2000_dac_range {
	SH2000_DAC_0_5V = 0,
	SH2000_DAC_0_10V = 1,
	SH2000_DAC_PM5V = 2,
	SH2000_DAC_PM10V = 3,
};

enum sh2000_param_type { SH2000_PT_F32 = 0, SH2000_PT_I32 = 1 };

/* What both sides know about a parameter: its name (as users see it), type,
 * valid range, default, and whether the card takes it while moving. Ranges
 * are inclusive; min_exclusive marks a strict lower bound (e.g. scale > 0).
 * Every front end asks this table; none keeps its own list. */
struct sh2000_param_info {
	uint16_t id;
	const char *name;
	enum sh2000_param_type type;
	double min, max;
	int min_exclusive;
	double def;
	/* 1: the card takes a new value while it moves (sh2000_state_moving):
	 * loop gains and limits that do not change the meaning of queued
	 * records, the heartbeat, the status period and the feed override
	 * (time_scale, time_ramp_ms). 0: refused with BUSY while moving. */
	int live;
};

/* The table (libsh2000/protocol/sh2000_protocol.c); NULL for unknown ids. */
const struct sh2000_param_info *sh2000_param_lookup(unsigned int id);
/* Range check shared by host validation and card acceptance: 0 if ok.
 * Also refuses NaN/infinity, non-integers for I32, values that are not a
 * normal binary32 for F32, HOME_VEL == 0 and a GANTRY_PAIR that is not
 * 0 or two axes. Cross-parameter rules
 * (SOFT_MIN < SOFT_MAX, coarse period divisible into fine steps) are the
 * card's: see SH2000_FW_* below and docs/protocol.md. */
int sh2000_param_in_range(const struct sh2000_param_info *p, double v);
/* The protocol minor version that brought parameter id (0: every 1.x
 * card has it). A host refuses it on a card that reports an older one. */
unsigned int sh2000_param_since_minor(unsigned int id);
/* Lookup by the user-visible name; NULL when unknown. */
const struct sh2000_param_info *sh2000_param_by_name(const char *name);
/* The names of the live parameters, space separated, in table order, for
 * messages ("only live parameters (...) may change now"). Returns buf. */
const char *sh2000_param_live_names(char *buf, size_t len);
/* The timing rule between coarse_period_us and fine_steps: the coarse period
 * in ns divides exactly by the fine steps, and the servo period it gives is
 * at least SH2000_FW_MIN_SERVO_NS. 1 when the pair is legal, else 0. */
int sh2000_timing_ok(long long coarse_us, long long fine_steps);
/* What "the card is moving" means everywhere: RUNNING, STOPPING or HOMING
 * (a state of enum sh2000_card_state). Non-live parameters and timing are
 * refused then. */
int sh2000_state_moving(unsigned int state);

/* ---------------------------------------------------------------------------
 * Firmware constants the host can rely on (docs/protocol.md "Faults").
 * ------------------------------------------------------------------------ */

/* A record step may exceed VMAX * coarse period by this fraction plus
 * SH2000_FW_VMAX_SLACK_COUNTS before it is rejected (REJECT_VELOCITY). */
#define SH2000_FW_VMAX_MARGIN		0.05
#define SH2000_FW_VMAX_SLACK_COUNTS	2.0
/* DAC at +-DAC_LIMIT for this many consecutive servo cycles: DAC_SAT. */
#define SH2000_FW_DAC_SAT_CYCLES	200u
/* Counter change in one servo cycle above 4 * VMAX * servo period plus
 * this many counts: COUNTER fault. */
#define SH2000_FW_COUNTER_SLACK		1000.0
/* Shortest servo period the firmware runs (coarse period / fine steps);
 * the coarse period in ns must also divide exactly by the fine steps. */
#define SH2000_FW_MIN_SERVO_NS		10000u
/* Homing with SH2000_HOME_F_INDEX creeps at |HOME_VEL| / this. */
#define SH2000_FW_HOME_CREEP_DIV	10.0

/* ---------------------------------------------------------------------------
 * Data gathering (protocol 1.2, docs/protocol.md section 17): the card
 * records chosen signals of each axis every PERIOD servo cycles into its
 * own memory; the host reads the record out afterwards through a window.
 * ------------------------------------------------------------------------ */

/* What can be recorded per axis: bit n of the axis' signal mask. Every
 * value is 32 bits: I32 two's complement or an F32 bit pattern. */
enum sh2000_gather_signal {
	SH2000_GS_SETPOINT = 0,		/* I32 counts: fine set-point, rounded */
	SH2000_GS_ENCODER = 1,		/* I32 counts: the counter, extended */
	SH2000_GS_FERR = 2,		/* F32 counts: set-point - encoder */
	SH2000_GS_DAC = 3,		/* I32 DAC code output */
	SH2000_GS_PID_P = 4,		/* F32 codes: Kp e */
	SH2000_GS_PID_I = 5,		/* F32 codes: u - P - D */
	SH2000_GS_PID_D = 6,		/* F32 codes: Kp Td/T (e - e1) */
	SH2000_GS_FF = 7,		/* F32 codes: KVFF v + KAFF a */
	SH2000_GS_VELOCITY = 8,		/* F32 counts/s: counter change / T */
	SH2000_GS_SETPOINT_VEL = 9,	/* F32 counts/s: the set-point's */
	SH2000_GATHER_SIGNALS = 10,	/* N: signals one axis can record */
};

/* GATHER_SET fields (CMD_PARAM); SIGNALS takes AXIS 0..3, the others
 * SH2000_AXIS_GLOBAL. */
enum sh2000_gather_field {
	SH2000_GF_SIGNALS = 0,		/* mask of 1 << SH2000_GS_* (0: none) */
	SH2000_GF_PERIOD = 1,		/* servo cycles per sample, 1..65535 */
	SH2000_GF_SAMPLES = 2,		/* samples in the record, >= 1 */
	SH2000_GF_TRIGGER = 3,		/* enum sh2000_gather_trigger */
	SH2000_GF_PRETRIGGER = 4,	/* samples kept from before it */
	SH2000_GATHER_FIELDS = 5,
};

enum sh2000_gather_trigger {
	SH2000_GATHER_NOW = 0,		/* in the cycle that takes GATHER_ARM */
	SH2000_GATHER_ON_MOTION = 1,	/* the next start of RUNNING/HOMING */
	SH2000_GATHER_ON_FAULT = 2,	/* the next card fault bit latched */
};

enum sh2000_gather_state {
	SH2000_GATHER_OFF = 0,		/* no record */
	SH2000_GATHER_ARMED = 1,	/* waiting for the trigger */
	SH2000_GATHER_RECORDING = 2,	/* triggered, filling the record */
	SH2000_GATHER_DONE = 3,		/* complete (or stopped): readable */
};

/* The card's record memory in 32-bit values: half of the DSP's SRAM
 * (2 x CY7C1021, 64 K x 32 bits in all), the project's assumption. A
 * card reports its own in GATHER_INFO. */
#define SH2000_GATHER_BUFFER_VALUES	32768u
/* GATHER_INFO's trigger index of a record that never triggered. */
#define SH2000_GATHER_NO_TRIGGER	0xffffffffu

/* What a host knows about a signal: its name as users see it
 * ("setpoint", "encoder", ...), type (SH2000_PT_F32/I32) and unit. */
struct sh2000_gather_signal_info {
	uint16_t id;
	const char *name;
	enum sh2000_param_type type;
	const char *unit;
};

/* NULL for ids >= SH2000_GATHER_SIGNALS / unknown names. */
const struct sh2000_gather_signal_info *sh2000_gather_signal_lookup(unsigned int id);
const struct sh2000_gather_signal_info *sh2000_gather_signal_by_name(const char *name);

/* Names for messages (never NULL). */
const char *sh2000_state_name(unsigned int state);
const char *sh2000_reject_name(unsigned int reason);
const char *sh2000_result_name(unsigned int result);
/* One bit of SH2000_W_FAULTS / SH2000_W_AXIS_FAULTS (v1.0 additions). */
const char *sh2000_fault_name(unsigned int bit);
const char *sh2000_axis_fault_name(unsigned int bit);


#ifdef __cplusplus
}
#endif

#endif /* SH2000_CARD_H */
