// SPDX-License-Identifier: MIT
/*
 * The card's queue of records (docs/protocol.md 7.2 and 7.6): what the
 * host published through the ring (HEAD) and posted through the mailbox
 * (protocol 1.3), in the order it arrived, counted in POSTED and consumed
 * from TAIL. Ring records stay in their slots until consumed; a mailbox
 * record is copied out of the RAM at once, since the host reuses the
 * mailbox for the next one.
 *
 * A host posts only while POSTED equals its count, so a new post is
 * always record POSTED; ring records may follow a post at once. HEAD is
 * therefore read before MBOX_SEQ: a HEAD that already counts ring records
 * behind a post was written after the post, which the second read then
 * sees too; the post is taken first, then HEAD - POSTED ring records.
 */
#include "cardmodel.h"

#define RD(fw, w)	sh2000_board_ram_read((fw)->hw, (w))
#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))

static unsigned int slot(uint16_t n)
{
	return n % SH2000_RING_RECORDS;
}

static int32_t ring_pos(struct sh2000_dsp *fw, uint16_t n, unsigned int a)
{
	unsigned int base = SH2000_W_RING_BASE + slot(n) * SH2000_RECORD_WORDS;

	return (int32_t)((uint32_t)RD(fw, base + SH2000_REC_POS_LO(a)) |
			 ((uint32_t)RD(fw, base + SH2000_REC_POS_HI(a)) << 16));
}

void sh2000_queue_boot(struct sh2000_dsp *fw)
{
	unsigned int a;

	/* whatever the host left is history, not a publication */
	fw->posted = RD(fw, SH2000_W_HEAD);
	fw->tail = fw->posted;
	fw->head_seen = fw->posted;
	fw->mbox_seq = RD(fw, SH2000_W_MBOX + SH2000_MBOX_SEQ);
	for (a = 0; a < SH2000_AXES; a++)
		fw->ref[a] = (int32_t)fw->ax[a].act;
	fw->queue_bad = 0;
	WR(fw, SH2000_W_POSTED, fw->posted);
	WR(fw, SH2000_W_TAIL, fw->tail);
}

uint16_t sh2000_queue_fill(const struct sh2000_dsp *fw)
{
	return (uint16_t)(fw->posted - fw->tail);
}

/* A post in the mailbox: copied into the queue as record POSTED. */
static void take_post(struct sh2000_dsp *fw)
{
	uint16_t m[SH2000_MBOX_WORDS];
	unsigned int i, a;
	uint16_t n = fw->posted;

	for (i = 0; i < SH2000_MBOX_WORDS; i++)
		m[i] = RD(fw, SH2000_W_MBOX + i);
	fw->posted++;
	if (sh2000_queue_fill(fw) > SH2000_RING_RECORDS) {
		fw->queue_bad = 1;	/* posted into a full queue */
		return;
	}
	if (m[SH2000_MBOX_CHECK] != sh2000_mbox_check(m)) {
		fw->via[slot(n)] = SH2000_VIA_MBOX_BAD;
		return;
	}
	/* the position is the previous record's plus the step, whether or
	 * not this one is numbered right: the host counts from it too */
	for (a = 0; a < SH2000_AXES; a++) {
		fw->ref[a] = sh2000_mbox_position(m, a, fw->ref[a]);
		fw->mbox_pos[slot(n)][a] = fw->ref[a];
	}
	/* another number: the post before it never reached the RAM */
	fw->via[slot(n)] = m[SH2000_MBOX_SEQ] == n ? SH2000_VIA_MBOX :
			   SH2000_VIA_MBOX_LOST;
}

/* HEAD changed: HEAD - POSTED ring records, 0 (HEAD put level with
 * POSTED after posts) or more than the room (a host bug). */
static void take_ring(struct sh2000_dsp *fw, uint16_t head)
{
	uint16_t d = (uint16_t)(head - fw->posted);
	unsigned int a;

	fw->head_seen = head;
	if (d == 0)
		return;
	if (d > SH2000_RING_RECORDS - sh2000_queue_fill(fw)) {
		/* the caller discards up to HEAD, as a ring-only card did */
		fw->queue_bad = 1;
		fw->posted = head;
		return;
	}
	for (; fw->posted != head; fw->posted++)
		fw->via[slot(fw->posted)] = SH2000_VIA_RING;
	for (a = 0; a < SH2000_AXES; a++)
		fw->ref[a] = ring_pos(fw, (uint16_t)(head - 1u), a);
}

void sh2000_queue_receive(struct sh2000_dsp *fw)
{
	uint16_t head = RD(fw, SH2000_W_HEAD);	/* first: see above */
	uint16_t seq = RD(fw, SH2000_W_MBOX + SH2000_MBOX_SEQ);

	if (seq != fw->mbox_seq) {
		fw->mbox_seq = seq;
		take_post(fw);
	}
	if (head != fw->head_seen)
		take_ring(fw, head);
	WR(fw, SH2000_W_POSTED, fw->posted);
}

void sh2000_queue_discard(struct sh2000_dsp *fw)
{
	sh2000_queue_receive(fw);
	fw->tail = fw->posted;
	WR(fw, SH2000_W_TAIL, fw->tail);
}

/*
 * Record TAIL in the ring's layout (a mailbox record with its number as
 * SEQ and a correct check word), consumed: TAIL += 1. Returns how it
 * came (enum sh2000_via); the caller rejects a lost or damaged post by
 * its number, *num.
 */
unsigned int sh2000_queue_take(struct sh2000_dsp *fw,
			       uint16_t rec[SH2000_RECORD_WORDS], uint16_t *num)
{
	uint16_t n = fw->tail;
	unsigned int via = fw->via[slot(n)], i, a;

	*num = n;
	if (via == SH2000_VIA_RING) {
		unsigned int base = SH2000_W_RING_BASE +
				    slot(n) * SH2000_RECORD_WORDS;

		for (i = 0; i < SH2000_RECORD_WORDS; i++)
			rec[i] = RD(fw, base + i);
	} else {
		for (a = 0; a < SH2000_AXES; a++) {
			uint32_t v = (uint32_t)fw->mbox_pos[slot(n)][a];

			rec[SH2000_REC_POS_LO(a)] = (uint16_t)(v & 0xffffu);
			rec[SH2000_REC_POS_HI(a)] = (uint16_t)(v >> 16);
		}
		rec[SH2000_REC_SEQ] = n;
		rec[SH2000_REC_FLAGS] = 0;
		rec[SH2000_REC_RESERVED] = 0;
		rec[SH2000_REC_CHECK] = sh2000_record_check(rec);
	}
	fw->tail++;
	WR(fw, SH2000_W_TAIL, fw->tail);
	return via;
}

/* SEQ of record TAIL, not consumed: what a rejection of it names. */
uint16_t sh2000_queue_first_seq(struct sh2000_dsp *fw)
{
	uint16_t n = fw->tail;

	if (fw->via[slot(n)] != SH2000_VIA_RING)
		return n;
	return RD(fw, SH2000_W_RING_BASE + slot(n) * SH2000_RECORD_WORDS +
		      SH2000_REC_SEQ);
}
