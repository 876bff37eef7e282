/* SPDX-License-Identifier: MIT */
/*
 * Changing the card's timing (coarse_period_us, fine_steps) through legal
 * states. The card takes the two one at a time and checks each against
 * the other's current value (sh2000_timing_ok()), so the order matters,
 * and sometimes no order of two sets works and the change needs states in
 * between. sh2000_timing_path() plans it (pure: hal_sh2000 runs the steps
 * from its real-time thread), sh2000_set_timing() plans and sends it.
 *
 * Of the paths it prefers, with SH2000_TIMING_NO_LONGER, one whose states
 * in between keep the servo period (coarse / fine) within the longer of
 * the two ends: the loops then run faster for a command's time, which a
 * stable loop stands, never slower, which could make it unstable.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sh2000_internal.h"

/* Values the search tries for each of the two, at most. */
#define CAND_MAX	48

struct cands {
	unsigned int v[CAND_MAX];
	unsigned int n;
};

static int in_range(unsigned int id, unsigned int v)
{
	return sh2000_param_in_range(sh2000_param_lookup(id), (double)v) == 0;
}

static int state_ok(unsigned int c, unsigned int f)
{
	return in_range(SH2000_GP_COARSE_PERIOD_US, c) &&
	       in_range(SH2000_GP_FINE_STEPS, f) && sh2000_timing_ok(c, f);
}

static uint64_t servo_ns(unsigned int c, unsigned int f)
{
	return (uint64_t)c * 1000u / f;
}

/* x's index in s, added if new (CAND_MAX when s is full). */
static unsigned int add(struct cands *s, unsigned int x)
{
	for (unsigned int i = 0; i < s->n; i++)
		if (s->v[i] == x)
			return i;
	if (s->n < CAND_MAX)
		s->v[s->n] = x;
	return s->n < CAND_MAX ? s->n++ : CAND_MAX;
}

/* x's divisors, the largest first. */
static void add_divisors(struct cands *s, unsigned int x)
{
	for (unsigned int d = 2; d <= x && s->n < CAND_MAX; d++)
		if (x % d == 0)
			add(s, x / d);
}

static unsigned int gcd(unsigned int a, unsigned int b)
{
	while (b) {
		unsigned int t = a % b;

		a = b;
		b = t;
	}
	return a;
}

/* A node (coarse C[i], fine F[j]) may be visited: legal, within bound. */
static int node_ok(const struct cands *C, const struct cands *F,
		   unsigned int k, uint64_t bound)
{
	unsigned int c = C->v[k / CAND_MAX], f = F->v[k % CAND_MAX];

	return k / CAND_MAX < C->n && k % CAND_MAX < F->n && state_ok(c, f) &&
	       servo_ns(c, f) <= bound;
}

/* Breadth first from node 0 (the start) to target over states that
 * change one of the two at a time: the fewest steps, into steps. */
static int search(const struct cands *C, const struct cands *F,
		  unsigned int target, uint64_t bound,
		  struct sh2000_timing_step *steps, unsigned int max)
{
	uint16_t from[CAND_MAX * CAND_MAX], queue[CAND_MAX * CAND_MAX];
	unsigned int head = 0, tail = 0, k, n = 0, at;
	const unsigned int start = 0;

	memset(from, 0xff, sizeof(from));
	from[start] = start;
	queue[tail++] = start;
	while (head < tail && from[target] == 0xffff) {
		k = queue[head++];
		for (unsigned int m = 0; m < C->n + F->n; m++) {
			unsigned int nk = m < C->n ? m * CAND_MAX + k % CAND_MAX :
				(k / CAND_MAX) * CAND_MAX + (m - C->n);

			if (from[nk] != 0xffff || !node_ok(C, F, nk, bound))
				continue;
			from[nk] = (uint16_t)k;
			queue[tail++] = (uint16_t)nk;
		}
	}
	if (from[target] == 0xffff)
		return -SH2000_EPARAM;
	for (at = target; at != start; at = from[at])
		n++;
	if (n > max)
		return -SH2000_EPARAM;
	for (at = target, k = n; at != start; at = from[at]) {
		unsigned int p = from[at];

		k--;
		if (p / CAND_MAX != at / CAND_MAX) {
			steps[k].id = SH2000_GP_COARSE_PERIOD_US;
			steps[k].value = C->v[at / CAND_MAX];
		} else {
			steps[k].id = SH2000_GP_FINE_STEPS;
			steps[k].value = F->v[at % CAND_MAX];
		}
	}
	return (int)n;
}

int sh2000_timing_path(unsigned int coarse0_us, unsigned int fine0,
		       unsigned int coarse_us, unsigned int fine_steps,
		       unsigned int flags, struct sh2000_timing_step *steps,
		       unsigned int max)
{
	struct cands C = { .n = 0 }, F = { .n = 0 };
	uint64_t bound = UINT64_MAX, s0, s1;
	unsigned int g, target;

	if (!state_ok(coarse_us, fine_steps) || !fine0)
		return -SH2000_EPARAM;
	s0 = servo_ns(coarse0_us, fine0);
	s1 = servo_ns(coarse_us, fine_steps);
	if (flags & SH2000_TIMING_NO_LONGER)
		bound = s0 > s1 ? s0 : s1;
	/* the start is node 0; the target's indices come next */
	add(&C, coarse0_us);
	add(&F, fine0);
	target = add(&C, coarse_us) * CAND_MAX + add(&F, fine_steps);
	if (target == 0)
		return 0;
	/* states in between: the ends' divisors, for the fine steps also
	 * the divisors of their least common multiple */
	add_divisors(&C, coarse0_us);
	add_divisors(&C, coarse_us);
	add_divisors(&F, fine0);
	add_divisors(&F, fine_steps);
	g = gcd(fine0, fine_steps);
	if ((uint64_t)fine0 / g * fine_steps <= UINT16_MAX)
		add_divisors(&F, fine0 / g * fine_steps);
	return search(&C, &F, target, bound, steps, max);
}

int sh2000_set_timing(struct sh2000 *h, unsigned int coarse_us,
		      unsigned int fine_steps)
{
	struct sh2000_timing_step st[SH2000_TIMING_STEPS_MAX];
	int32_t c0 = 0, f0 = 0, wc, wf;
	int n, r;

	pthread_mutex_lock(&h->lock);
	/* the same refusal as sh2000_param_set() for a value out of range */
	r = sh2000_param_check(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US,
			       coarse_us, &wc);
	if (!r)
		r = sh2000_param_check(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS,
				       fine_steps, &wf);
	if (!r && !sh2000_timing_ok(coarse_us, fine_steps))
		r = sh2000_fail(h, -SH2000_EPARAM,
				"global parameters coarse_period_us %u with fine_steps %u: the servo period must be a whole number of ns >= %u ns",
				coarse_us, fine_steps, SH2000_FW_MIN_SERVO_NS);
	/* from the card's values: another program may have changed them */
	if (!r)
		r = sh2000_global_get_locked(h, SH2000_GP_COARSE_PERIOD_US, &c0);
	if (!r)
		r = sh2000_global_get_locked(h, SH2000_GP_FINE_STEPS, &f0);
	if (r)
		goto out;
	n = sh2000_timing_path((unsigned int)c0, (unsigned int)f0, coarse_us,
			       fine_steps, SH2000_TIMING_NO_LONGER, st,
			       SH2000_TIMING_STEPS_MAX);
	if (n < 0)
		n = sh2000_timing_path((unsigned int)c0, (unsigned int)f0,
				       coarse_us, fine_steps, 0, st,
				       SH2000_TIMING_STEPS_MAX);
	if (n < 0)
		r = sh2000_fail(h, -SH2000_EPARAM,
				"global parameters coarse_period_us %u with fine_steps %u: no order of sets reaches them from %d with %d through legal states",
				coarse_us, fine_steps, (int)c0, (int)f0);
	for (int i = 0; !r && i < n; i++)
		r = sh2000_global_set_locked(h, st[i].id, (int32_t)st[i].value);
out:
	pthread_mutex_unlock(&h->lock);
	return r;
}
