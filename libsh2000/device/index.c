/* SPDX-License-Identifier: MIT */
/*
 * The index latch a host arms while the card runs a stream (protocol 1.6,
 * docs/protocol.md 13.1): arming and disarming it, and reading what the
 * card latched from the axis' index block. The block is 813 port cycles
 * above the status words, so a host reads it when the axis' state bits
 * say the arm ended (INDEX_ARMED gone), not every poll.
 */
#include <errno.h>
#include <math.h>

#include "sh2000_internal.h"

int sh2000_index_supported(struct sh2000 *h)
{
	return sh2000_need_minor(h, SH2000_PROTO_MINOR_INDEX,
				 "arming the index latch while it runs needs");
}

static int check_axis(struct sh2000 *h, const char *what, unsigned int axis)
{
	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "%s: no axis %u", what, axis);
	return sh2000_index_supported(h);
}

int sh2000_index_arm(struct sh2000 *h, unsigned int axis, unsigned int flags,
		     double within_mm)
{
	int32_t value = 0;
	double c;
	int r = check_axis(h, "index_arm", axis);

	if (r)
		return r;
	c = nearbyint(fabs(within_mm) * h->scale[axis]);
	if (!isfinite(c) || c > INT32_MAX)
		return sh2000_fail(h, -EINVAL,
				   "index_arm: %g mm is not a travel in 32-bit counts",
				   within_mm);
	r = sh2000_command(h, SH2000_CMD_INDEX_ARM, axis, flags, (int32_t)c, &value);
	return r < 0 ? r : (int)(value & 0xffff);
}

int sh2000_index_disarm(struct sh2000 *h, unsigned int axis)
{
	int r = check_axis(h, "index_disarm", axis);

	return r ? r : sh2000_command(h, SH2000_CMD_INDEX_DISARM, axis, 0, 0, NULL);
}

/* b[] as the host sees it: the counter extended from the status' encoder,
 * the cycle from the status' snapshot cycle. */
static void decode(const struct sh2000 *h, unsigned int axis, const uint16_t *b,
		   const struct sh2000_status *st, struct sh2000_index *ix)
{
	int64_t pos = st->axis[axis].pos_counts;
	uint32_t c = (uint32_t)b[SH2000_IX_COUNT_LO] |
		     ((uint32_t)b[SH2000_IX_COUNT_HI] << 16);
	uint32_t at = (uint32_t)b[SH2000_IX_CYCLE_LO] |
		      ((uint32_t)b[SH2000_IX_CYCLE_HI] << 16);

	ix->state = b[SH2000_IX_STATE];
	ix->arm = b[SH2000_IX_ARM];
	ix->counts = 0;
	ix->cycle = 0;
	if (ix->state == SH2000_INDEX_LATCHED) {
		ix->counts = pos + sh2000_counter_delta(c & SH2000_COUNTER_MASK,
				(uint32_t)pos & SH2000_COUNTER_MASK);
		ix->cycle = st->card_cycle +
			    (uint64_t)(int64_t)(int32_t)(at - (uint32_t)st->card_cycle);
	}
	ix->mm = h->scale[axis] > 0 ? (double)ix->counts / h->scale[axis] : 0;
}

int sh2000_index_read(struct sh2000 *h, unsigned int axis,
		      const struct sh2000_status *st, struct sh2000_index *ix)
{
	uint16_t b[SH2000_INDEX_WORDS];
	int r;

	if (axis >= SH2000_AXES || !st || !ix)
		return -EINVAL;
	r = sh2000_index_supported(h);
	if (r)
		return r;
	if (pthread_mutex_trylock(&h->lock))
		return -EAGAIN;
	h->nb.active = 1;
	r = sh2000_rd(h, SH2000_W_INDEX(axis), SH2000_INDEX_WORDS, b);
	h->nb.active = 0;
	if (!r && b[SH2000_IX_CHECK] != sh2000_index_check(b))
		r = -EAGAIN;	/* the card was writing it */
	if (!r)
		decode(h, axis, b, st, ix);
	pthread_mutex_unlock(&h->lock);
	return r;
}
