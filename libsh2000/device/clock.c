/* SPDX-License-Identifier: MIT */
/*
 * The handle's clock: virtual card time for `sim` (waits advance the model
 * with the lock held, since the model is the caller's to serialise), real
 * time otherwise (waits release the lock so other threads get the card).
 */
#include <errno.h>
#include <sched.h>
#include <time.h>

#include "sh2000_internal.h"

uint64_t sh2000_mono_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

void sh2000_sleep_real(uint64_t ns)
{
	struct timespec ts = { (time_t)(ns / 1000000000ull),
			       (long)(ns % 1000000000ull) };

	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

uint64_t sh2000_now_locked(struct sh2000 *h)
{
	return h->be->now_ns ? h->be->now_ns(h) : sh2000_mono_ns();
}

void sh2000_hold_wait(struct sh2000 *h, uint64_t ns)
{
	if (h->be->virtual_time) {
		h->be->wait_ns(h, ns);
		/* an emergency stop from another thread goes first: a mutex
		 * released and retaken at once would starve it */
		pthread_mutex_unlock(&h->lock);
		while (__atomic_load_n(&h->cmd.urgent, __ATOMIC_ACQUIRE))
			sched_yield();
		pthread_mutex_lock(&h->lock);
		return;
	}
	pthread_mutex_unlock(&h->lock);
	sh2000_sleep_real(ns);
	pthread_mutex_lock(&h->lock);
}

uint64_t sh2000_now_ns(struct sh2000 *h)
{
	uint64_t t;

	pthread_mutex_lock(&h->lock);
	t = sh2000_now_locked(h);
	pthread_mutex_unlock(&h->lock);
	return t;
}

int sh2000_sleep_ns(struct sh2000 *h, uint64_t ns)
{
	pthread_mutex_lock(&h->lock);
	sh2000_hold_wait(h, ns);
	pthread_mutex_unlock(&h->lock);
	return 0;
}

