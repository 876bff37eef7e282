/* SPDX-License-Identifier: MIT */
/*
 * Taking and giving up the motion: the arbiter's motion lock, and the
 * mailbox around it. A new holder takes the record count where the last
 * holder left it; a holder letting go puts HEAD level with the count for
 * a later host that knows only the ring. Sequenced here, above both, so
 * that the arbiter never calls into the mailbox.
 */
#include "sh2000_internal.h"

int sh2000_motion_claim_locked(struct sh2000 *h)
{
	int r = sh2000_arb_claim_locked(h);

	if (r <= 0)
		return r;
	/* the record count is where the last holder left it */
	r = sh2000_queue_sync_locked(h);
	if (r < 0)
		sh2000_arb_release_locked(h);
	return r;
}

int sh2000_claim_motion(struct sh2000 *h)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_motion_claim_locked(h);
	pthread_mutex_unlock(&h->lock);
	return r;
}

void sh2000_release_motion(struct sh2000 *h)
{
	pthread_mutex_lock(&h->lock);
	if (sh2000_arb_holds_motion(h))
		(void)sh2000_mbox_close_locked(h);
	sh2000_arb_release_locked(h);
	pthread_mutex_unlock(&h->lock);
}
