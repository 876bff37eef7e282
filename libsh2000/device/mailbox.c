/* SPDX-License-Identifier: MIT */
/*
 * The point mailbox (protocol 1.3, docs/protocol.md 7.6), host side: one
 * point per servo tick posted in words 56..63, just above the status a
 * poll has read (about 24 port cycles instead of a seek into the ring and
 * back), and the count of records both ways share with the ring.
 *
 * h->head counts the records published either way; the HEAD word is
 * written only with ring records. A post needs POSTED equal to that count
 * (the card has taken the last post and every ring record); when it is
 * not (a card late by a servo cycle), the point goes through the ring,
 * which may follow a post at once. A post carries positions as 20-bit
 * steps from the previous record, so it is used only while both sides
 * know that record: since the last ring publication, and while the last
 * poll saw the card running the motion (a fault or a stop ends that).
 */
#include <stdlib.h>

#include "sh2000_internal.h"

/* A host that posts still beats while polls are rare: the card stops a
 * motion whose host is silent for SH2000_GP_HOST_TIMEOUT_MS. */
#define MBOX_KEEPALIVE_NS	1000000ull

int sh2000_mbox_card(const struct sh2000 *h)
{
	return SH2000_PROTO_VERSION_MINOR(h->card_version) >=
	       SH2000_PROTO_MINOR_MAILBOX;
}

/* A new count restarts the segment numbers from it (they are the
 * records' numbers); an unchanged one keeps them. */
static void count_is(struct sh2000 *h, uint16_t head)
{
	if (head != h->head) {
		h->head = head;
		h->segments = head;
	}
}

int sh2000_queue_sync_locked(struct sh2000 *h)
{
	uint16_t head, w[8];
	int r;

	r = sh2000_rd(h, SH2000_W_HEAD, 1, &head);
	if (r < 0)
		return r;
	if (!sh2000_mbox_card(h)) {
		count_is(h, head);
		return 0;
	}
	r = sh2000_rd(h, SH2000_W_POSTED, 8, w);
	if (r < 0)
		return r;
	/* ring records the card has not received yet count; HEAD behind
	 * POSTED is a host that posted since */
	count_is(h, (int16_t)(head - w[0]) > 0 ? head : w[0]);
	h->mbox.seq = w[1 + SH2000_MBOX_SEQ];
	h->mbox.ref_ok = 0;
	return 0;
}

/* 1 when the card has received every record published, 0 when not yet
 * (one word read on the way up to the mailbox). */
static int all_received(struct sh2000 *h)
{
	uint16_t posted;
	int r;

	r = sh2000_rd(h, SH2000_W_POSTED, 1, &posted);
	return r < 0 ? r : posted == h->head;
}

void sh2000_mbox_ring_written(struct sh2000 *h,
			      const int32_t last[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		h->mbox.ref[a] = last[a];
	h->mbox.ref_ok = 1;
	h->mbox.dirty = 0;
}

/* The mailbox can carry pt: a card that has it, a record both sides
 * know before it, no flag only a ring record has, steps it can carry,
 * and a number the mailbox does not hold already (the card would see
 * no change). */
static int usable(const struct sh2000 *h, const int32_t pt[SH2000_AXES],
		  unsigned int flags)
{
	unsigned int a;

	if (!sh2000_mbox_card(h) || !h->mbox.ref_ok || !h->mbox.running ||
	    (flags & SH2000_PUSH_END) ||
	    h->head == h->mbox.seq)
		return 0;
	for (a = 0; a < SH2000_AXES; a++)
		if (llabs((long long)pt[a] - (long long)h->mbox.ref[a]) >
		    SH2000_MBOX_STEP_MAX)
			return 0;
	return 1;
}

int sh2000_mbox_post_locked(struct sh2000 *h, const int32_t pt[SH2000_AXES],
			    unsigned int flags)
{
	uint16_t m[SH2000_MBOX_WORDS];
	uint64_t now;
	unsigned int a;
	int r;

	if (!usable(h, pt, flags))
		return 0;
	/* POSTED, then the record (SEQ last): one upward stream */
	r = all_received(h);
	if (r <= 0)
		return r;	/* not yet: the ring */
	sh2000_mbox_pack(m, pt, h->head);
	r = sh2000_wr(h, SH2000_W_MBOX, SH2000_MBOX_WORDS, m);
	if (r < 0)
		return r;
	h->mbox.seq = h->head;
	h->mbox.dirty = 1;
	h->head++;
	h->segments++;
	for (a = 0; a < SH2000_AXES; a++)
		h->mbox.ref[a] = pt[a];
	now = sh2000_now_locked(h);
	if (now - h->host_hb_ns >= MBOX_KEEPALIVE_NS) {
		r = sh2000_wr1(h, SH2000_W_HOST_HEARTBEAT, ++h->host_hb);
		if (r < 0)
			return r;
		h->host_hb_ns = now;
	}
	return 1;
}

void sh2000_mbox_status(struct sh2000 *h, unsigned int card_state)
{
	/* a card that is not running may have refused records: the next
	 * motion starts through the ring, which tells the card every
	 * position whole */
	h->mbox.running = card_state == SH2000_STATE_RUNNING;
	if (!h->mbox.running)
		h->mbox.ref_ok = 0;
}

int sh2000_mbox_close_locked(struct sh2000 *h)
{
	int r;

	/* only the handle that posted last: any other's count is stale
	 * (sh2000ctl beside a stream). A post the card has not taken yet is
	 * below the new HEAD: the card takes it first, as with ring records
	 * behind a post. */
	if (!h->mbox.dirty)
		return 0;
	r = sh2000_wr1(h, SH2000_W_HEAD, h->head);
	if (!r)
		h->mbox.dirty = 0;
	return r;
}
