/* SPDX-License-Identifier: MIT */
/*
 * Protocol v1 between the host (libsh2000) and the card's DSP firmware (the
 * card model in libsh2000/cardmodel/), spoken through the 1024-word
 * dual-port RAM. docs/protocol.md is the prose version of this file; the two
 * must agree. Both sides include this header: there is no other copy of the
 * layout.
 *
 * Rules that hold for every word:
 *  - every word has exactly one writer (the "owner" column below);
 *  - a 16-bit word is read and written atomically; anything wider is either
 *    inside the versioned snapshot (card -> host) or written before a
 *    sequence word that publishes it (host -> card);
 *  - 32-bit values are two words, low word first, two's complement;
 *  - the host polls from word 0 upwards, so what it needs most is first.
 */
#ifndef SH2000_PROTOCOL_H
#define SH2000_PROTOCOL_H

#include <stdint.h>

#define SH2000_PROTO_MAGIC		0x5348u	/* "SH" */
#define SH2000_PROTO_MAJOR		1u
#define SH2000_PROTO_MINOR		0u
#define SH2000_PROTO_VERSION		((SH2000_PROTO_MAJOR << 8) | SH2000_PROTO_MINOR)
#define SH2000_PROTO_VERSION_MAJOR(v)	(((v) >> 8) & 0xffu)
#define SH2000_PROTO_VERSION_MINOR(v)	((v) & 0xffu)

#define SH2000_AXES			4u

/* ---------------------------------------------------------------------------
 * RAM layout (word addresses). Owner: C = card writes, H = host writes.
 * ------------------------------------------------------------------------ */

/* H: emergency stop request. The host changes the value (increments it);
 * the card acts within one servo cycle when it differs from ESTOP_ACK. At
 * word 0 so that it is two port cycles (clear, write) from anywhere. */
#define SH2000_W_ESTOP_REQ		0u
/* C: constant after the firmware starts; fixed at these addresses in every
 * protocol version so that any host can tell what it is talking to. */
#define SH2000_W_MAGIC			1u
#define SH2000_W_VERSION		2u
/* C: +1 every servo cycle (mod 2^16): the card heartbeat. */
#define SH2000_W_HEARTBEAT		3u
/* C: the ESTOP_REQ value the card has acted on. */
#define SH2000_W_ESTOP_ACK		4u
/* C: enum sh2000_card_state. */
#define SH2000_W_STATE			5u
/* C: latched SH2000_FAULT_* bits of the card (not of an axis). */
#define SH2000_W_FAULTS			6u
/* C: records consumed from the segment ring, free-running mod 2^16. */
#define SH2000_W_TAIL			7u
/* C: command acknowledgement. Written in the order VALUE, RESULT, ACK so a
 * host that reads ACK first and then RESULT/VALUE sees a finished answer. */
#define SH2000_W_CMD_ACK		8u
#define SH2000_W_CMD_RESULT		9u
#define SH2000_W_CMD_VALUE_LO		10u
#define SH2000_W_CMD_VALUE_HI		11u
/* C: the last rejected segment record (seed 004's CNCERR). COUNT changes
 * on every rejection, so a repeated SEQ is still seen as new. */
#define SH2000_W_REJECT_SEQ		12u
#define SH2000_W_REJECT_REASON		13u
#define SH2000_W_REJECT_COUNT		14u
/* C: per axis, latched SH2000_AXIS_FAULT_* bits. */
#define SH2000_W_AXIS_FAULTS(a)		(15u + (a))
/* C: per axis, SH2000_AXIS_* state bits. */
#define SH2000_W_AXIS_STATE(a)		(19u + (a))

/*
 * C: the versioned snapshot of the multi-word values. The card writes
 * SNAP_SEQ_BEGIN = s + 1 first, then the body, then SNAP_SEQ_END = s + 1.
 * END sits below the body and BEGIN above it, so a host streaming upwards
 * reads END, body, BEGIN; the body is consistent when both are equal. The
 * card publishes it every SH2000_GP_STATUS_PERIOD servo cycles (not every
 * cycle, so that a host poll rarely overlaps a publication).
 */
#define SH2000_W_SNAP_SEQ_END		23u
#define SH2000_W_SNAP_AXIS(a)		(24u + 5u * (a))
#define   SH2000_SNAP_CMD_LO		0u	/* set-point, counts (int32) */
#define   SH2000_SNAP_CMD_HI		1u
#define   SH2000_SNAP_ACT_LO		2u	/* encoder counter, 28 bits */
#define   SH2000_SNAP_ACT_HI		3u
#define   SH2000_SNAP_DAC		4u	/* DAC code, int16 */
#define SH2000_SNAP_AXIS_WORDS		5u
#define SH2000_W_SNAP_TIME_LO		44u	/* servo cycle of the snapshot */
#define SH2000_W_SNAP_TIME_HI		45u
#define SH2000_W_SNAP_SEQ_BEGIN		46u
/* End of the card-written status: a full poll reads words 0..46. */
#define SH2000_STATUS_WORDS		47u

/* H: +1 on every host poll or push. A card in motion that sees no change
 * for SH2000_GP_HOST_TIMEOUT_MS stops and latches SH2000_FAULT_HOST_TIMEOUT. */
#define SH2000_W_HOST_HEARTBEAT		47u
/* H: records published into the ring, free-running mod 2^16. */
#define SH2000_W_HEAD			48u
/* H: one command. OP..CHECK are written first, SEQ last; the host does
 * not touch them again until CMD_ACK == CMD_SEQ. */
#define SH2000_W_CMD_OP			49u
#define SH2000_W_CMD_AXIS		50u
#define SH2000_W_CMD_PARAM		51u
#define SH2000_W_CMD_ARG_LO		52u
#define SH2000_W_CMD_ARG_HI		53u
#define SH2000_W_CMD_CHECK		54u	/* sh2000_cmd_check() */
#define SH2000_W_CMD_SEQ		55u

/* Segment ring: RING_RECORDS records of RECORD_WORDS words from RING_BASE. */
#define SH2000_W_RING_BASE		64u
#define SH2000_RING_RECORDS		64u	/* power of two dividing 2^16 */
#define SH2000_RECORD_WORDS		12u
#define SH2000_W_RING_END \
	(SH2000_W_RING_BASE + SH2000_RING_RECORDS * SH2000_RECORD_WORDS)
/* Words RING_END..1023 are reserved in v1: both sides leave them alone. */

/* Word offsets inside one record. */
#define SH2000_REC_POS_LO(a)		(2u * (a))	/* int32 counts */
#define SH2000_REC_POS_HI(a)		(2u * (a) + 1u)
#define SH2000_REC_SEQ			8u	/* host's segment number */
#define SH2000_REC_FLAGS		9u	/* SH2000_REC_F_* */
#define SH2000_REC_RESERVED		10u	/* must be 0 */
#define SH2000_REC_CHECK		11u	/* sh2000_record_check() */

/* The last record of a motion: after it the card pads its B-spline window
 * with this point, reaches it exactly and goes idle (no underrun). */
#define SH2000_REC_F_END		0x0001u
#define SH2000_REC_F_ALL		SH2000_REC_F_END	/* others reserved */

/*
 * Ring rules. fill = (HEAD - TAIL) mod 2^16, always 0..RING_RECORDS.
 * Record n lives in slot n mod RING_RECORDS.
 *  - host: writes record HEAD only while fill < RING_RECORDS, then HEAD += 1;
 *  - card: reads record TAIL only while fill > 0, then TAIL += 1 after it
 *    has copied the record out of the RAM.
 * A fill above RING_RECORDS is a host bug: the card latches
 * SH2000_FAULT_PROTOCOL.
 */

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

/* Axis state bits (SH2000_W_AXIS_STATE), live. */
#define SH2000_AXIS_ENABLED		0x0001u
#define SH2000_AXIS_HOMED		0x0002u
#define SH2000_AXIS_HOMING		0x0004u
#define SH2000_AXIS_MOVING		0x0008u
#define SH2000_AXIS_LIMIT_POS		0x0010u	/* + limit switch active */
#define SH2000_AXIS_LIMIT_NEG		0x0020u	/* - limit switch active */
#define SH2000_AXIS_HOME_SW		0x0040u	/* home switch active */
#define SH2000_AXIS_INDEX		0x0080u	/* index seen since homing */

/* Why a record was rejected (SH2000_W_REJECT_REASON). */
enum sh2000_reject_reason {
	SH2000_REJECT_NONE = 0,
	SH2000_REJECT_CHECKSUM = 1,	/* record check word wrong */
	SH2000_REJECT_RESERVED = 2,	/* reserved word or flag bit set */
	SH2000_REJECT_VELOCITY = 3,	/* step exceeds an axis' max velocity */
	SH2000_REJECT_SOFT_LIMIT = 4,	/* point beyond a soft limit */
	SH2000_REJECT_DISABLED = 5,	/* moves an axis that is not enabled */
	SH2000_REJECT_STATE = 6,	/* card not in a state to move */
	/* v1.0 addition: the record was consumed but not executed (the card
	 * model's SH2000_INJECT_DROP_SEGMENT; a real card uses it for a
	 * record lost inside the firmware). Handled like any rejection. */
	SH2000_REJECT_DROPPED = 7,
};

/* ---------------------------------------------------------------------------
 * Commands (seed 004's CNC/RSP): one at a time, each acknowledged.
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
};

/* SH2000_W_CMD_AXIS value addressing a global parameter. */
#define SH2000_AXIS_GLOBAL		0xffffu

/* HOME flags */
#define SH2000_HOME_F_INDEX		0x0001u	/* finish on the encoder index */

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
	SH2000_GP_FIRST = SH2000_GP_COARSE_PERIOD_US,
	SH2000_GP_END = 36,
};

enum sh2000_dac_range {
	SH2000_DAC_0_5V = 0,
	SH2000_DAC_0_10V = 1,
	SH2000_DAC_PM5V = 2,
	SH2000_DAC_PM10V = 3,
};

enum sh2000_param_type { SH2000_PT_F32 = 0, SH2000_PT_I32 = 1 };

/* What both sides know about a parameter: its name (as users see it), type,
 * valid range and default. Ranges are inclusive; min_exclusive marks a
 * strict lower bound (e.g. scale > 0). */
struct sh2000_param_info {
	uint16_t id;
	const char *name;
	enum sh2000_param_type type;
	double min, max;
	int min_exclusive;
	double def;
};

/* The table (libsh2000/protocol/sh2000_protocol.c); NULL for unknown ids. */
const struct sh2000_param_info *sh2000_param_lookup(unsigned int id);
/* Range check shared by host validation and card acceptance: 0 if ok.
 * Also refuses NaN/infinity, non-integers for I32, values that are not a
 * normal binary32 for F32, and HOME_VEL == 0. Cross-parameter rules
 * (SOFT_MIN < SOFT_MAX, coarse period divisible into fine steps) are the
 * card's: see SH2000_FW_* below and docs/protocol.md. */
int sh2000_param_in_range(const struct sh2000_param_info *p, double v);
/* Lookup by the user-visible name; NULL when unknown. */
const struct sh2000_param_info *sh2000_param_by_name(const char *name);

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
 * Check words: a 16-bit Fletcher-style sum that catches any single flipped
 * word and swapped words. One implementation for both sides.
 * ------------------------------------------------------------------------ */

static inline uint16_t sh2000_check16(const uint16_t *w, unsigned int n)
{
	uint32_t a = 0x5a, b = 0xa5;
	unsigned int i;

	for (i = 0; i < n; i++) {
		a = (a + w[i]) % 65521u;
		b = (b + a) % 65521u;
	}
	return (uint16_t)(a ^ (b << 5) ^ (b >> 11));
}

/* Check word of a record: over words 0..RECORD_WORDS-2. */
static inline uint16_t sh2000_record_check(const uint16_t *rec)
{
	return sh2000_check16(rec, SH2000_RECORD_WORDS - 1u);
}

/* Check word of a command: over OP, AXIS, PARAM, ARG_LO, ARG_HI and the SEQ
 * it will be published with. */
static inline uint16_t sh2000_cmd_check(uint16_t seq, uint16_t op,
					uint16_t axis, uint16_t param,
					uint16_t arg_lo, uint16_t arg_hi)
{
	const uint16_t w[6] = { seq, op, axis, param, arg_lo, arg_hi };

	return sh2000_check16(w, 6);
}

/* Names for messages (never NULL). */
const char *sh2000_state_name(unsigned int state);
const char *sh2000_reject_name(unsigned int reason);
const char *sh2000_result_name(unsigned int result);
/* One bit of SH2000_W_FAULTS / SH2000_W_AXIS_FAULTS (v1.0 additions). */
const char *sh2000_fault_name(unsigned int bit);
const char *sh2000_axis_fault_name(unsigned int bit);

#endif /* SH2000_PROTOCOL_H */
