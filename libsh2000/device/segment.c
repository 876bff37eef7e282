/* SPDX-License-Identifier: MIT */
/*
 * The segment ring: all-or-nothing batches (room checked first, records
 * written, HEAD published once), waits for room or idle, and the latched
 * faults that end them.
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "sh2000_internal.h"

#define WAIT_POLL_NS	100000ull
#define WAIT_MAX_NS	5000000ull
/* A waiting host still beats: the card stops a motion whose host is
 * silent for SH2000_GP_HOST_TIMEOUT_MS (keep that >= 10 ms). */
#define KEEPALIVE_NS	1000000ull

/*
 * Words HEARTBEAT..TAIL in one read: enough to see a stopped card, a
 * latched fault (then a full poll names it) and the ring fill.
 */
static int quick(struct sh2000 *h, unsigned int *fill, unsigned int *state,
		 int keepalive)
{
	struct sh2000_status st;
	uint16_t w[5];
	uint64_t now;
	int r;

	r = sh2000_rd(h, SH2000_W_HEARTBEAT, 5, w);
	if (r < 0)
		return r;
	if (sh2000_hb_note(h, w[0], sh2000_now_locked(h)) >= h->hb.limit_ns ||
	    h->hb.unsure || w[3] ||
	    w[2] == SH2000_STATE_FAULT || w[2] == SH2000_STATE_ESTOP) {
		r = sh2000_poll_locked(h, &st);
		if (r < 0)
			return r;
		r = sh2000_status_error_locked(h, &st);
		if (r < 0)
			return r;
	}
	now = sh2000_now_locked(h);
	if (keepalive && now - h->host_hb_ns >= KEEPALIVE_NS) {
		r = sh2000_wr1(h, SH2000_W_HOST_HEARTBEAT, ++h->host_hb);
		if (r < 0)
			return r;
		h->host_hb_ns = now;
	}
	*fill = (uint16_t)(h->head - w[4]);
	*state = w[2];
	if (*fill > SH2000_RING_RECORDS)
		return sh2000_fail(h, -SH2000_EPROTOCOL,
				   "ring fill %u (HEAD %u, TAIL %u) is impossible",
				   *fill, h->head, w[4]);
	return 0;
}

int sh2000_ring_write_locked(struct sh2000 *h,
			     const int32_t (*pts)[SH2000_AXES], size_t n,
			     unsigned int flags)
{
	uint16_t rec[SH2000_RING_RECORDS * SH2000_RECORD_WORDS];
	uint16_t pub[2];
	unsigned int slot, first, i, a;
	int r;

	for (i = 0; i < n; i++) {
		uint16_t *w = &rec[i * SH2000_RECORD_WORDS];

		for (a = 0; a < SH2000_AXES; a++) {
			uint32_t v = (uint32_t)pts[i][a];

			w[SH2000_REC_POS_LO(a)] = (uint16_t)(v & 0xffffu);
			w[SH2000_REC_POS_HI(a)] = (uint16_t)(v >> 16);
		}
		w[SH2000_REC_SEQ] = (uint16_t)(h->segments + i);
		w[SH2000_REC_FLAGS] = (flags & SH2000_PUSH_END) && i == n - 1 ?
				      SH2000_REC_F_END : 0;
		w[SH2000_REC_RESERVED] = 0;
		w[SH2000_REC_CHECK] = sh2000_record_check(w);
	}
	slot = h->head % SH2000_RING_RECORDS;
	first = SH2000_RING_RECORDS - slot;
	if (first > n)
		first = (unsigned int)n;
	r = sh2000_wr(h, SH2000_W_RING_BASE + slot * SH2000_RECORD_WORDS,
		      first * SH2000_RECORD_WORDS, rec);
	if (!r && first < n)
		r = sh2000_wr(h, SH2000_W_RING_BASE,
			      ((unsigned int)n - first) * SH2000_RECORD_WORDS,
			      &rec[first * SH2000_RECORD_WORDS]);
	if (r < 0)
		return r;
	/* one publication: host heartbeat and HEAD, adjacent words */
	pub[0] = ++h->host_hb;
	pub[1] = (uint16_t)(h->head + n);
	r = sh2000_wr(h, SH2000_W_HOST_HEARTBEAT, 2, pub);
	if (r < 0)
		return r;
	h->host_hb_ns = sh2000_now_locked(h);
	h->head = pub[1];
	h->segments += n;
	sh2000_mbox_ring_written(h, pts[n - 1]);
	return (int)n;
}

static int push_locked(struct sh2000 *h, const int32_t (*pts)[SH2000_AXES],
		       size_t n, unsigned int flags)
{
	unsigned int fill, state;
	int r;

	/* the ring is the motion's: the first push claims it */
	r = sh2000_motion_claim_locked(h);
	if (r < 0)
		return r;
	r = quick(h, &fill, &state, 0);
	if (r < 0)
		return r;
	if (SH2000_RING_RECORDS - fill < n)
		return sh2000_fail(h, -SH2000_EQUEUE_FULL,
				   "batch of %zu records: %u free in the ring",
				   n, SH2000_RING_RECORDS - fill);
	return sh2000_ring_write_locked(h, pts, n, flags);
}

static int check_batch(struct sh2000 *h, size_t n)
{
	if (n > SH2000_RING_RECORDS)
		return sh2000_fail(h, -EMSGSIZE,
				   "batch of %zu records: the ring holds %u",
				   n, SH2000_RING_RECORDS);
	return 0;
}

int sh2000_push_counts(struct sh2000 *h, const int32_t (*pts)[SH2000_AXES],
		       size_t n, unsigned int flags)
{
	int r = check_batch(h, n);

	if (r || !n)
		return r;
	pthread_mutex_lock(&h->lock);
	r = push_locked(h, pts, n, flags);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_push_mm(struct sh2000 *h, const double (*pts)[SH2000_AXES],
		   size_t n, unsigned int flags)
{
	int32_t c[SH2000_RING_RECORDS][SH2000_AXES];
	size_t i;
	unsigned int a;
	int r = check_batch(h, n);

	if (r || !n)
		return r;
	pthread_mutex_lock(&h->lock);
	for (i = 0; i < n; i++) {
		for (a = 0; a < SH2000_AXES; a++) {
			double v = nearbyint(pts[i][a] * h->scale[a]);

			if (!isfinite(v) || v < INT32_MIN || v > INT32_MAX) {
				r = sh2000_fail(h, -SH2000_EPARAM,
						"point %zu axis %u: %g mm is not representable in 32-bit counts",
						i, a, pts[i][a]);
				goto out;
			}
			c[i][a] = (int32_t)v;
		}
	}
	r = push_locked(h, (const int32_t (*)[SH2000_AXES])c, n, flags);
out:
	pthread_mutex_unlock(&h->lock);
	return r;
}

uint64_t sh2000_next_segment(struct sh2000 *h)
{
	uint64_t s;

	pthread_mutex_lock(&h->lock);
	s = h->segments;
	pthread_mutex_unlock(&h->lock);
	return s;
}

int sh2000_queue_free(struct sh2000 *h)
{
	unsigned int fill, state;
	int r;

	pthread_mutex_lock(&h->lock);
	r = quick(h, &fill, &state, 1);
	if (!r)
		r = (int)(SH2000_RING_RECORDS - fill);
	pthread_mutex_unlock(&h->lock);
	return r;
}

/*
 * How long to sleep before looking again: half the time the card needs to
 * consume `records` (so a streaming host wakes a few times per batch, not
 * every 100 us), within 100 us..5 ms (well inside the heartbeat limit and
 * the host timeout).
 */
static uint64_t wait_step(struct sh2000 *h, unsigned int records)
{
	uint64_t ns = (uint64_t)records * (uint64_t)(h->coarse_us > 0 ?
						     h->coarse_us : 0) * 500u;

	if (ns < WAIT_POLL_NS)
		ns = WAIT_POLL_NS;
	if (ns > WAIT_MAX_NS)
		ns = WAIT_MAX_NS;
	return ns;
}

static int wait_for(struct sh2000 *h, unsigned int n, int idle, int timeout_ms)
{
	unsigned int fill, state;
	uint64_t t0, limit;
	int r;

	if (!idle && n > SH2000_RING_RECORDS)
		return check_batch(h, n);
	pthread_mutex_lock(&h->lock);
	t0 = sh2000_now_locked(h);
	limit = timeout_ms < 0 ? UINT64_MAX : (uint64_t)timeout_ms * 1000000ull;
	for (;;) {
		r = quick(h, &fill, &state, 1);
		if (r < 0)
			break;
		if (idle ? fill == 0 && state == SH2000_STATE_IDLE :
		    SH2000_RING_RECORDS - fill >= n) {
			r = (int)(SH2000_RING_RECORDS - fill);
			break;
		}
		if (sh2000_now_locked(h) - t0 >= limit) {
			r = sh2000_fail(h, -SH2000_ETIMEOUT,
					idle ? "not idle after %d ms (state %s, %u records queued)" :
					"no room after %d ms (state %s, %u records queued)",
					timeout_ms, sh2000_state_name(state), fill);
			break;
		}
		sh2000_hold_wait(h, wait_step(h, idle ? fill :
					      n - (SH2000_RING_RECORDS - fill)));
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_wait_space(struct sh2000 *h, unsigned int n, int timeout_ms)
{
	return wait_for(h, n, 0, timeout_ms);
}

int sh2000_wait_idle(struct sh2000 *h, int timeout_ms)
{
	int r = wait_for(h, 0, 1, timeout_ms);

	if (r < 0)
		return r;
	/* the next poll shows where the motion ended, not a snapshot from
	 * before its last cycles */
	pthread_mutex_lock(&h->lock);
	r = sh2000_fresh_snapshot(h, SH2000_CMD_TIMEOUT_MS);
	pthread_mutex_unlock(&h->lock);
	return r < 0 ? r : 0;
}

int sh2000_wait_rest(struct sh2000 *h, int timeout_ms)
{
	uint64_t t0 = sh2000_now_ns(h), limit;
	struct sh2000_status st;
	int r;

	limit = timeout_ms < 0 ? UINT64_MAX : (uint64_t)timeout_ms * 1000000ull;
	for (;;) {
		r = sh2000_poll(h, &st);
		if (r < 0)
			return r;
		if (!sh2000_state_moving(st.card_state))
			return 0;
		if (sh2000_now_ns(h) - t0 >= limit)
			break;
		/* a stop lasts tens of milliseconds: a poll each */
		r = sh2000_sleep_ns(h, 1000000ull);
		if (r < 0)
			return r;
	}
	pthread_mutex_lock(&h->lock);
	r = sh2000_fail(h, -SH2000_ETIMEOUT, "still %s after %g s",
			sh2000_state_name(st.card_state), timeout_ms / 1e3);
	pthread_mutex_unlock(&h->lock);
	return r;
}

unsigned int sh2000_queue_size(const struct sh2000 *h)
{
	(void)h;	/* one ring size in protocol v1 */
	return SH2000_RING_RECORDS;
}
