/* SPDX-License-Identifier: MIT */
/*
 * Protocol v1 between the host (libsh2000) and the card's DSP firmware (the
 * card model in libsh2000/sim/cardmodel/), spoken through the 1024-word
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
#include <string.h>

#include "sh2000/card.h"

#define SH2000_PROTO_MAGIC		0x5348u	/* "SH" */

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
/* C: the last rejected segment record (the CNC communication paper's [R5] CNCERR). COUNT changes
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

/*
 * Protocol 1.3 (SH2000_PROTO_MINOR_MAILBOX): the point mailbox, in words
 * 56..63 that were reserved. A host that sends one point per tick posts it
 * here, on its way up from the poll, instead of seeking into the ring and
 * back down to HEAD; the card copies it into its own queue within a servo
 * cycle. docs/protocol.md 7.6.
 *
 * C: records the card has received (mod 2^16), through the ring (HEAD) or
 * the mailbox: the number the next record gets. Equals HEAD for a host
 * that only uses the ring.
 */
#define SH2000_W_POSTED			56u
/* H: one record, MBOX_SEQ written last (it posts the record). A position
 * travels as its low SH2000_MBOX_POS_BITS bits; the card takes the value
 * with those bits nearest the previous record's position. */
#define SH2000_W_MBOX			57u
#define   SH2000_MBOX_POS_LO(a)		(a)	/* bits 0..15 of axis a */
#define   SH2000_MBOX_POS_HI		4u	/* bits 16..19, axis a in 4a..4a+3 */
#define   SH2000_MBOX_CHECK		5u	/* sh2000_mbox_check() */
#define   SH2000_MBOX_SEQ		6u	/* the record's number (POSTED) */
#define SH2000_MBOX_WORDS		7u
#define SH2000_MBOX_POS_BITS		20u
/* The largest step from the previous record a mailbox record carries. */
#define SH2000_MBOX_STEP_MAX		((1 << (SH2000_MBOX_POS_BITS - 1)) - 1)

/* Segment ring: RING_RECORDS records of RECORD_WORDS words from RING_BASE. */
#define SH2000_W_RING_BASE		64u
#define SH2000_RING_RECORDS		64u	/* power of two dividing 2^16 */
#define SH2000_RECORD_WORDS		12u
#define SH2000_W_RING_END \
	(SH2000_W_RING_BASE + SH2000_RING_RECORDS * SH2000_RECORD_WORDS)

/*
 * Protocol 1.4 (SH2000_PROTO_MINOR_FIRST_FAULT): the first-fault record,
 * in words 832..836 that were reserved after the ring (the status words
 * 0..46 have no free word, and 47..63 are the host's). C: which fault
 * latched first since the last RESET (or boot), and in which servo cycle:
 * FAULTS and AXIS_FAULTS(a) are bit sets and keep no order. The card
 * writes it once, in the cycle the first fault bit latches and before it
 * publishes that bit in FAULTS/AXIS_FAULTS: AXIS, CYCLE, CHECK, then BIT
 * last. RESET writes BIT := 0 first, then the rest 0. So a host that sees
 * a fault bit in the status words finds the record already written; it
 * reads the five words upwards and takes them when BIT != 0 and CHECK
 * matches (a mismatch: a RESET, perhaps a new first fault, while it read;
 * read again). The record does not change until RESET, so a host reads it
 * once per fault, not every poll. docs/protocol.md 10.1.
 */
#define SH2000_W_FIRST_FAULT		832u
#define   SH2000_FF_BIT			0u	/* the SH2000_FAULT_* or
						 * SH2000_AXIS_FAULT_* bit;
						 * 0: none since RESET */
#define   SH2000_FF_AXIS		1u	/* 0..3: an axis fault;
						 * SH2000_AXIS_GLOBAL: a card
						 * fault */
#define   SH2000_FF_CYCLE_LO		2u	/* servo cycle it latched in */
#define   SH2000_FF_CYCLE_HI		3u	/* (mod 2^32, as SNAP_TIME) */
#define   SH2000_FF_CHECK		4u	/* sh2000_first_fault_check() */
#define SH2000_FIRST_FAULT_WORDS	5u
/* Words SH2000_W_FIRST_FAULT + SH2000_FIRST_FAULT_WORDS ..
 * SH2000_W_GATHER_BASE-1 are reserved (but for the blocks below): both
 * sides leave them alone. */

/*
 * Protocol 1.6 (SH2000_PROTO_MINOR_INDEX): the index blocks, one per
 * axis, in words 860..887 that were reserved (just below the
 * compensation status of 1.5). C: what became of the
 * axis' last INDEX_ARM (enum sh2000_index_state), the arm's number (the
 * command's VALUE), and for a latched mark the FPGA's 28-bit counter at
 * the mark and the servo cycle whose sampling found it (the mark passed
 * in the period before that cycle). The card writes a block when its
 * state changes, within the cycle, before it publishes the axis'
 * INDEX_ARMED / INDEX_LATCHED bits: the words, CHECK, then STATE last. A
 * host reads it once it sees the bits change (not every poll: it is 813
 * port cycles above the status words) and takes it when CHECK matches
 * (else read again). docs/protocol.md 13.1.
 */
#define SH2000_W_INDEX(a)		(860u + 7u * (a))
#define   SH2000_IX_STATE		0u	/* enum sh2000_index_state */
#define   SH2000_IX_ARM			1u	/* +1 per INDEX_ARM (mod 2^16) */
#define   SH2000_IX_COUNT_LO		2u	/* counter at the mark, 28 bits */
#define   SH2000_IX_COUNT_HI		3u
#define   SH2000_IX_CYCLE_LO		4u	/* servo cycle (mod 2^32, as */
#define   SH2000_IX_CYCLE_HI		5u	/* SNAP_TIME) */
#define   SH2000_IX_CHECK		6u	/* sh2000_index_check() */
#define SH2000_INDEX_WORDS		7u

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
 * Ring rules. fill = (HEAD - TAIL) mod 2^16, always 0..RING_RECORDS
 * (from 1.3: POSTED - TAIL). Record n lives in slot n mod RING_RECORDS.
 *  - host: writes record HEAD only while fill < RING_RECORDS, then HEAD += 1;
 *  - card: reads record TAIL only while fill > 0, then TAIL += 1 after it
 *    has copied the record out of the RAM.
 * A fill above RING_RECORDS is a host bug: the card latches
 * SH2000_FAULT_PROTOCOL.
 *
 * From 1.3 a record reaches the card through the ring or the mailbox, and
 * both count in POSTED (docs/protocol.md 7.6). The host's count c is the
 * records it has published either way:
 *  - ring: records c..c+n-1 in their slots, then HEAD := c + n;
 *  - mailbox: the record's words, then MBOX_SEQ := c;
 *  - a post only while POSTED = c (the card has received everything);
 *    ring records at any time, a post's number left out of the ring.
 * The card, every servo cycle, reads HEAD and then MBOX_SEQ: a changed
 * MBOX_SEQ is record POSTED; a changed HEAD brings HEAD - POSTED ring
 * records after it (0: none, a host putting HEAD level with POSTED; more
 * than the room: SH2000_FAULT_PROTOCOL).
 */

/* ---------------------------------------------------------------------------
 * Protocol 1.2: the gather window (docs/protocol.md section 17). C: written
 * only in answer to GATHER_INFO and GATHER_READ, all of it before CMD_ACK,
 * and not again before the next such command; the host reads it after
 * CMD_ACK while it still holds the command slot. The check word covers
 * words 1..HEADER-1 and the COUNT payload words, so a reader knows the
 * window is whole and is the answer to its own command.
 * ------------------------------------------------------------------------ */

#define SH2000_W_GATHER_BASE		896u
#define SH2000_GATHER_WINDOW_WORDS	128u	/* to word 1023 */
#define   SH2000_GW_CHECK		0u	/* sh2000_gather_check() */
#define   SH2000_GW_SEQ			1u	/* CMD_SEQ answered */
#define   SH2000_GW_KIND		2u	/* SH2000_GATHER_KIND_* */
#define   SH2000_GW_RECORD		3u	/* record number (+1 per ARM) */
#define   SH2000_GW_COUNT		4u	/* payload words that follow */
#define   SH2000_GW_OFFSET_LO		5u	/* DATA: first value's index */
#define   SH2000_GW_OFFSET_HI		6u
#define   SH2000_GW_STATE		7u	/* enum sh2000_gather_state */
#define SH2000_GW_HEADER		8u	/* payload from word 8 */
#define SH2000_GATHER_CHUNK_VALUES \
	((SH2000_GATHER_WINDOW_WORDS - SH2000_GW_HEADER) / 2u)

#define SH2000_GATHER_KIND_INFO		1u
#define SH2000_GATHER_KIND_DATA		2u

/* INFO payload (word offsets after the header); 32-bit values low first. */
#define SH2000_GI_TRIGGER		0u	/* enum sh2000_gather_trigger */
#define SH2000_GI_PERIOD		1u	/* servo cycles per sample */
#define SH2000_GI_VALUES		2u	/* values per sample */
#define SH2000_GI_SIGNALS(a)		(3u + (a))	/* mask per axis */
#define SH2000_GI_SAMPLES_LO		7u	/* samples in the record now */
#define SH2000_GI_CAPACITY_LO		9u	/* samples configured */
#define SH2000_GI_PRETRIGGER_LO		11u	/* pre-trigger configured */
#define SH2000_GI_TRIGGER_INDEX_LO	13u	/* sample at/after the trigger,
						 * 0xffffffff: not triggered */
#define SH2000_GI_FIRST_CYCLE_LO	15u	/* servo cycle of sample 0 */
#define SH2000_GI_TRIGGER_CYCLE_LO	17u	/* cycle the trigger fired */
#define SH2000_GI_BUFFER_LO		19u	/* the card's record memory,
						 * 32-bit values */
#define SH2000_GATHER_INFO_WORDS	21u

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

/* Check word of the gather window w[0..HEADER+count-1] (count payload
 * words): over words 1..HEADER-1 and the payload. */
static inline uint16_t sh2000_gather_check(const uint16_t *w,
					   unsigned int count)
{
	return sh2000_check16(w + 1, SH2000_GW_HEADER - 1u + count);
}

/* Check word of the first-fault record r[0..FIRST_FAULT_WORDS-1]: over
 * BIT, AXIS, CYCLE_LO and CYCLE_HI. */
static inline uint16_t sh2000_first_fault_check(const uint16_t *r)
{
	return sh2000_check16(r, SH2000_FF_CHECK);
}

/* Check word of an index block b[0..INDEX_WORDS-1]: over STATE..CYCLE_HI. */
static inline uint16_t sh2000_index_check(const uint16_t *b)
{
	return sh2000_check16(b, SH2000_IX_CHECK);
}

/* Check word of a mailbox record: over the position words and the SEQ it
 * is posted with (so a record is bound to its number, like a command). */
static inline uint16_t sh2000_mbox_check(const uint16_t *m)
{
	const uint16_t w[6] = { m[0], m[1], m[2], m[3], m[SH2000_MBOX_POS_HI],
				m[SH2000_MBOX_SEQ] };

	return sh2000_check16(w, 6);
}

/* The mailbox words of record `seq` at positions pos[] (check included). */
static inline void sh2000_mbox_pack(uint16_t m[SH2000_MBOX_WORDS],
				    const int32_t pos[SH2000_AXES], uint16_t seq)
{
	unsigned int a;

	m[SH2000_MBOX_POS_HI] = 0;
	for (a = 0; a < SH2000_AXES; a++) {
		uint32_t v = (uint32_t)pos[a];

		m[SH2000_MBOX_POS_LO(a)] = (uint16_t)(v & 0xffffu);
		m[SH2000_MBOX_POS_HI] |= (uint16_t)(((v >> 16) & 0xfu) << (4 * a));
	}
	m[SH2000_MBOX_SEQ] = seq;
	m[SH2000_MBOX_CHECK] = sh2000_mbox_check(m);
}

/* Axis a's position in mailbox words m: the value whose low 20 bits m
 * carries that is nearest ref, the previous record's position. Exact when
 * the step from ref is within SH2000_MBOX_STEP_MAX. */
static inline int32_t sh2000_mbox_position(const uint16_t *m, unsigned int a,
					   int32_t ref)
{
	const uint32_t mask = (1u << SH2000_MBOX_POS_BITS) - 1u;
	uint32_t low = (uint32_t)m[SH2000_MBOX_POS_LO(a)] |
		       ((uint32_t)((m[SH2000_MBOX_POS_HI] >> (4 * a)) & 0xfu) << 16);
	uint32_t d = (low - (uint32_t)ref) & mask;

	if (d & (1u << (SH2000_MBOX_POS_BITS - 1)))
		d |= ~mask;	/* sign-extend the 20-bit step */
	return (int32_t)((uint32_t)ref + d);
}

/* ---------------------------------------------------------------------------
 * The encoder counters are 28 bits wide and wrap (docs/card.md); the
 * snapshot's ACT words carry them as they are. Whoever reads them extends
 * them with the sign-extended difference of two readings.
 * ------------------------------------------------------------------------ */

#define SH2000_COUNTER_BITS		28u
#define SH2000_COUNTER_MASK		((1u << SH2000_COUNTER_BITS) - 1u)

/* Signed difference now - before of two counter readings, assuming the
 * counter moved less than half its range in between. */
static inline int32_t sh2000_counter_delta(uint32_t now, uint32_t before)
{
	uint32_t d = (now - before) & SH2000_COUNTER_MASK;

	if (d & (1u << (SH2000_COUNTER_BITS - 1u)))
		return (int32_t)d - (int32_t)(1u << SH2000_COUNTER_BITS);
	return (int32_t)d;
}

/* A counter reading as a signed 28-bit value. */
static inline int32_t sh2000_counter_signed(uint32_t v)
{
	return sh2000_counter_delta(v & SH2000_COUNTER_MASK, 0);
}

/* ---------------------------------------------------------------------------
 * F32 parameter values travel as IEEE-754 binary32 bit patterns in two
 * words. One encoding for both sides: the library and the card model.
 * ------------------------------------------------------------------------ */

static inline uint32_t sh2000_f32_bits(double v)
{
	float f = (float)v;
	uint32_t b;

	memcpy(&b, &f, sizeof(b));
	return b;
}

static inline double sh2000_f32_value(uint32_t b)
{
	float f;

	memcpy(&f, &b, sizeof(f));
	return (double)f;
}

/* ===========================================================================
 * Protocol 1.5 (SH2000_PROTO_MINOR_COMP): compensation tables, docs/protocol.md
 * section 18 and docs/compensation.md. One self-contained block.
 *
 * A table set travels as one image of 16-bit words (layout below). The host
 * holds the command slot for the whole load: COMP_BEGIN (ARG = the image's
 * words) empties the card's staging memory; for each page it writes the
 * words into the page window and sends COMP_PAGE (ARG = the page's first
 * word, in order, PARAM = its count); COMP_COMMIT (ARG = sh2000_comp_sum()
 * of the whole image) makes the card check the sum, the layout and the
 * tables against its axes' parameters, and switch to them only at rest
 * (BUSY while moving: nothing changes, the staging is kept for a retry).
 * A refusal changes nothing that is active. The switch (and COMP_CLEAR)
 * blends from the old corrections to the new over SH2000_COMP_BLEND_MS with
 * a smoothstep, so the set-point never steps.
 * ======================================================================== */

/* H: the page window: the gather window's words, which only the holder of
 * the command slot uses (the card writes them only in answer to GATHER_INFO
 * and GATHER_READ). Word 0 is sh2000_comp_page_check(), the page from 1. */
#define SH2000_W_COMP_PAGE		SH2000_W_GATHER_BASE
#define SH2000_COMP_PAGE_WORDS		(SH2000_GATHER_WINDOW_WORDS - 1u)

/* C: the active tables, in the last reserved words before the gather
 * window; written at every switch, CHECK last (a host that reads a CHECK
 * that does not match reads again). */
#define SH2000_W_COMP_STATUS		888u
#define   SH2000_CS_STATE		0u	/* enum sh2000_comp_state
						 * (sh2000/comp.h) */
#define   SH2000_CS_TABLES		1u	/* tables active */
#define   SH2000_CS_ID_LO		2u	/* the image's identity */
#define   SH2000_CS_ID_HI		3u
#define   SH2000_CS_SUM_LO		4u	/* its sh2000_comp_sum() */
#define   SH2000_CS_SUM_HI		5u
#define   SH2000_CS_GEN			6u	/* +1 per switch (mod 2^16) */
#define   SH2000_CS_CHECK		7u	/* check16 of words 0..6 */
#define SH2000_COMP_STATUS_WORDS	8u

/* What the card holds (SH2000_COMP_MAX_WORDS, _TABLES) is in the public
 * sh2000/comp.h, with the rules the image is checked by. */
#include "sh2000/comp.h"

#define SH2000_COMP_BLEND_MS		200u

/* The image: a header, then each table: a descriptor and its data.
 * 32-bit values take two words, low first; I32 two's complement, F32 the
 * binary32 bit pattern (as parameters). Positions and corrections in
 * counts of the axes concerned. */
#define SH2000_CI_MAGIC			0u	/* SH2000_COMP_MAGIC */
#define SH2000_CI_FORMAT		1u	/* SH2000_COMP_FORMAT */
#define SH2000_CI_ID_LO			2u	/* chosen by the host */
#define SH2000_CI_ID_HI			3u
#define SH2000_CI_TABLES		4u	/* 0..SH2000_COMP_MAX_TABLES */
#define SH2000_CI_RESERVED		5u	/* 0 */
#define SH2000_COMP_HEADER_WORDS	6u
#define SH2000_COMP_MAGIC		0x4354u	/* "CT" */
#define SH2000_COMP_FORMAT		1u

/* Table descriptor words. */
#define SH2000_CT_KIND			0u	/* enum sh2000_comp_kind */
#define SH2000_CT_TARGET		1u	/* axis corrected */
#define SH2000_CT_SRC1			2u	/* axis whose position is read */
#define SH2000_CT_SRC2			3u	/* GRID: the second one, else 0 */
#define SH2000_CT_N1			4u	/* points (GRID: along SRC1) */
#define SH2000_CT_N2			5u	/* GRID: points along SRC2, else 0 */
#define SH2000_COMP_DESC_WORDS		6u

enum sh2000_comp_kind {
	/* correction of TARGET as a function of SRC1's position: a pitch
	 * table when SRC1 = TARGET, straightness when not. Data: N1 I32
	 * positions, strictly increasing, then N1 F32 corrections; cubic
	 * Hermite between them; beyond the ends the slope runs out over
	 * SH2000_COMP_RUNOUT end segments, then the correction holds. */
	SH2000_COMP_TABLE = 1,
	/* TARGET += coefficient * SRC1's position (squareness). N1 = 0;
	 * data: one F32 (counts per count, i.e. rad). */
	SH2000_COMP_SQUARE = 2,
	/* correction of TARGET as a function of SRC1 and SRC2 (flatness):
	 * a uniform N1 x N2 grid. Data: I32 U0, DU > 0 (SRC1), V0, DV > 0
	 * (SRC2), then N1 * N2 F32 corrections, SRC1 fastest; bicubic
	 * Hermite inside, the same run-out beyond the edges. */
	SH2000_COMP_GRID = 3,
};

/* COMP_COMMIT's VALUE when refused with BAD_VALUE: the table (0..), the
 * point in it and why (enum sh2000_comp_reason, sh2000/comp.h). */
#define SH2000_COMP_FAULT(table, point, reason) \
	(((uint32_t)(reason) << 24) | (((uint32_t)(table) & 0xffu) << 16) | \
	 ((uint32_t)(point) & 0xffffu))
#define SH2000_COMP_FAULT_REASON(v)	(((v) >> 24) & 0xffu)
#define SH2000_COMP_FAULT_TABLE(v)	(((v) >> 16) & 0xffu)
#define SH2000_COMP_FAULT_POINT(v)	((v) & 0xffffu)

/* The image's sum: Fletcher-32 over its words. */
static inline uint32_t sh2000_comp_sum(const uint16_t *w, size_t n)
{
	uint32_t a = 0xffffu, b = 0xffffu;
	size_t i;

	for (i = 0; i < n; i++) {
		a = (a + w[i]) % 65535u;
		b = (b + a) % 65535u;
	}
	return (b << 16) | a;
}

/* Check word of a page: over its first word's number, its count and its
 * words (so a page is bound to its place in the image). */
static inline uint16_t sh2000_comp_page_check(uint32_t first,
					      const uint16_t *w,
					      unsigned int count)
{
	uint32_t a = 0x5a, b = 0xa5;
	uint16_t head[3] = { (uint16_t)(first & 0xffffu),
			     (uint16_t)(first >> 16), (uint16_t)count };
	unsigned int i;

	for (i = 0; i < 3u + count; i++) {
		a = (a + (i < 3u ? head[i] : w[i - 3u])) % 65521u;
		b = (b + a) % 65521u;
	}
	return (uint16_t)(a ^ (b << 5) ^ (b >> 11));
}

#endif /* SH2000_PROTOCOL_H */
