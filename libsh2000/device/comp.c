// SPDX-License-Identifier: MIT
/*
 * Compensation tables on the card (protocol 1.5, docs/protocol.md section
 * 18): an image paged through the window and switched to, cleared, or the
 * active set's identity read from the status words. The whole load is one
 * hold of the command slot, so no other program's command lands between
 * the pages; each page is bound to its place by its check word and sent
 * again when the card finds it torn.
 */
#include <errno.h>
#include <string.h>

#include "sh2000_internal.h"

#define PAGE_TRIES	3
#define STATUS_TRIES	5
/* How long a switch's blend may take to end, and how often to look. */
#define BLEND_WAIT_NS	(4ull * SH2000_COMP_BLEND_MS * 1000000ull)
#define BLEND_POLL_NS	5000000ull

static int need_comp(struct sh2000 *h)
{
	return sh2000_need_minor(h, SH2000_PROTO_MINOR_COMP, "compensation tables need");
}

static int send_page(struct sh2000 *h, const uint16_t *w, uint32_t first,
		     unsigned int count)
{
	uint16_t page[1 + SH2000_COMP_PAGE_WORDS];
	int tries, r = 0;

	memcpy(&page[1], &w[first], count * sizeof(w[0]));
	page[0] = sh2000_comp_page_check(first, &page[1], count);
	for (tries = 0; tries < PAGE_TRIES; tries++) {
		r = sh2000_wr(h, SH2000_W_COMP_PAGE, count + 1u, page);
		if (!r)
			r = sh2000_cmd_exchange(h, SH2000_CMD_COMP_PAGE, 0, count,
						(int32_t)first, NULL,
						SH2000_CMD_TIMEOUT_MS);
		if (r != -SH2000_ECMD_CHECKSUM)
			return r;
	}
	return r;
}

static void fault_of(int32_t v, struct sh2000_comp_fault *f)
{
	uint32_t u = (uint32_t)v, t = SH2000_COMP_FAULT_TABLE(u);
	uint32_t p = SH2000_COMP_FAULT_POINT(u);

	f->table = t == 0xffu ? -1 : (int)t;
	f->point = p == 0xffffu ? -1 : (int)p;
	f->reason = (enum sh2000_comp_reason)SH2000_COMP_FAULT_REASON(u);
}

static int load_locked(struct sh2000 *h, const uint16_t *w, size_t n,
		       struct sh2000_comp_fault *fault)
{
	int32_t value = 0;
	uint32_t first;
	int r = sh2000_cmd_slot_take(h, "comp load");

	if (r < 0)
		return r;
	r = sh2000_cmd_exchange(h, SH2000_CMD_COMP_BEGIN, 0, 0, (int32_t)n,
				&value, SH2000_CMD_TIMEOUT_MS);
	for (first = 0; !r && first < n; first += SH2000_COMP_PAGE_WORDS) {
		size_t left = n - first;

		r = send_page(h, w, first,
			      (unsigned int)(left < SH2000_COMP_PAGE_WORDS ?
					     left : SH2000_COMP_PAGE_WORDS));
	}
	if (!r)
		r = sh2000_cmd_exchange(h, SH2000_CMD_COMP_COMMIT, 0, 0,
					(int32_t)sh2000_comp_sum(w, n), &value,
					SH2000_CMD_TIMEOUT_MS);
	sh2000_cmd_slot_drop(h);
	if (r == -SH2000_ECMD_VALUE || r == -SH2000_ECMD_CHECKSUM) {
		struct sh2000_comp_fault f;

		fault_of(value, &f);
		if (fault)
			*fault = f;
		return sh2000_fail(h, r, "comp load: the card refused table %d, point %d: %s",
				   f.table, f.point, sh2000_comp_reason_name(f.reason));
	}
	if (r == -SH2000_ECMD_BUSY)
		return sh2000_fail(h, r, "tables switch only at rest: the card is moving or still blending the last switch");
	return r;
}

/* After a switch: wait (bounded) until the card's blend has ended, so
 * that the next switch or a status shows the new set in place. */
static int blend_wait(struct sh2000 *h)
{
	uint64_t t0 = sh2000_now_locked(h);
	uint16_t w[SH2000_COMP_STATUS_WORDS];
	int r;

	for (;;) {
		r = sh2000_rd(h, SH2000_W_COMP_STATUS, SH2000_COMP_STATUS_WORDS, w);
		if (r < 0)
			return r;
		if (w[SH2000_CS_CHECK] == sh2000_check16(w, SH2000_CS_CHECK) &&
		    w[SH2000_CS_STATE] != SH2000_COMP_SWITCHING)
			return 0;
		if (sh2000_now_locked(h) - t0 > BLEND_WAIT_NS)
			return sh2000_fail(h, -SH2000_ETIMEOUT,
					   "the card did not finish its %u ms blend to the new tables",
					   SH2000_COMP_BLEND_MS);
		sh2000_hold_wait(h, BLEND_POLL_NS);
	}
}

int sh2000_comp_load_image(struct sh2000 *h, const uint16_t *w, size_t n,
			   struct sh2000_comp_fault *fault)
{
	int r;

	if (!h || !w)
		return -EINVAL;
	if (n > SH2000_COMP_MAX_WORDS)
		return sh2000_fail(h, -SH2000_EPARAM,
				   "comp load: %zu words: the card holds %u",
				   n, SH2000_COMP_MAX_WORDS);
	pthread_mutex_lock(&h->lock);
	r = need_comp(h);
	if (!r)
		r = load_locked(h, w, n, fault);
	if (!r)
		r = blend_wait(h);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_comp_clear(struct sh2000 *h)
{
	int r;

	if (!h)
		return -EINVAL;
	pthread_mutex_lock(&h->lock);
	r = need_comp(h);
	if (!r)
		r = sh2000_command_locked(h, SH2000_CMD_COMP_CLEAR, 0, 0, 0, NULL,
					  SH2000_CMD_TIMEOUT_MS);
	if (r == -SH2000_ECMD_BUSY)
		r = sh2000_fail(h, r, "tables switch only at rest: the card is moving or still blending the last switch");
	if (!r)
		r = blend_wait(h);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_comp_status(struct sh2000 *h, struct sh2000_comp_status *st)
{
	uint16_t w[SH2000_COMP_STATUS_WORDS];
	int tries, r;

	if (!h || !st)
		return -EINVAL;
	pthread_mutex_lock(&h->lock);
	r = need_comp(h);
	for (tries = 0; !r && tries < STATUS_TRIES; tries++) {
		r = sh2000_rd(h, SH2000_W_COMP_STATUS, SH2000_COMP_STATUS_WORDS, w);
		if (!r && w[SH2000_CS_CHECK] == sh2000_check16(w, SH2000_CS_CHECK))
			break;
	}
	if (!r && tries == STATUS_TRIES)
		r = sh2000_fail(h, -SH2000_ETORN,
				"comp status: the words kept changing");
	pthread_mutex_unlock(&h->lock);
	if (r)
		return r;
	memset(st, 0, sizeof(*st));
	st->state = w[SH2000_CS_STATE];
	st->tables = w[SH2000_CS_TABLES];
	st->id = (uint32_t)sh2000_w32(&w[SH2000_CS_ID_LO]);
	st->sum = (uint32_t)sh2000_w32(&w[SH2000_CS_SUM_LO]);
	st->generation = w[SH2000_CS_GEN];
	return 0;
}

int sh2000_comp_limits_get(struct sh2000 *h, struct sh2000_comp_limits *lim)
{
	static const unsigned int ids[2] = { SH2000_P_VMAX, SH2000_P_AMAX };
	double *dst[2] = { lim->vmax, lim->amax };
	unsigned int a, k;
	int r;

	double scale;

	/* the library's parameters are in mm; the rule is in counts */
	for (a = 0; a < SH2000_AXES; a++) {
		r = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &scale);
		for (k = 0; !r && k < 2; k++) {
			r = sh2000_param_get(h, (int)a, ids[k], &dst[k][a]);
			dst[k][a] *= scale;
		}
		if (r < 0)
			return r;
	}
	return 0;
}
