/* SPDX-License-Identifier: MIT */
/*
 * The card's timing changed through legal states: sh2000_timing_path()
 * on its own (every step legal, the servo period in between within the
 * longer end when asked, the target reached, the fewest steps where the
 * answer is known) and sh2000_set_timing() on the in-process card, which
 * refuses any illegal step itself.
 */
#include "simtest.h"

/* Walk steps from (c, f): every state legal and in range, within bound;
 * returns the end in *c, *f. */
static void walk(unsigned int *c, unsigned int *f,
		 const struct sh2000_timing_step *st, int n, uint64_t bound)
{
	const struct sh2000_param_info *pc =
		sh2000_param_lookup(SH2000_GP_COARSE_PERIOD_US);
	const struct sh2000_param_info *pf =
		sh2000_param_lookup(SH2000_GP_FINE_STEPS);

	for (int i = 0; i < n; i++) {
		if (st[i].id == SH2000_GP_COARSE_PERIOD_US)
			*c = st[i].value;
		else if (st[i].id == SH2000_GP_FINE_STEPS)
			*f = st[i].value;
		else
			fail_msg("step %d: parameter %u", i, st[i].id);
		if (!sh2000_timing_ok(*c, *f) ||
		    sh2000_param_in_range(pc, *c) || sh2000_param_in_range(pf, *f))
			fail_msg("step %d: (%u, %u) is not a legal state", i, *c, *f);
		if ((uint64_t)*c * 1000u / *f > bound)
			fail_msg("step %d: (%u, %u): servo period %llu ns beyond %llu",
				 i, *c, *f,
				 (unsigned long long)((uint64_t)*c * 1000u / *f),
				 (unsigned long long)bound);
	}
}

static int path(unsigned int c0, unsigned int f0, unsigned int c1,
		unsigned int f1, unsigned int flags,
		struct sh2000_timing_step *st)
{
	int n = sh2000_timing_path(c0, f0, c1, f1, flags, st,
				   SH2000_TIMING_STEPS_MAX);
	unsigned int c = c0, f = f0;
	uint64_t s0 = (uint64_t)c0 * 1000u / f0, s1 = (uint64_t)c1 * 1000u / f1;

	if (n >= 0) {
		walk(&c, &f, st, n, flags & SH2000_TIMING_NO_LONGER ?
		     (s0 > s1 ? s0 : s1) : UINT64_MAX);
		if (c != c1 || f != f1)
			fail_msg("(%u, %u) -> (%u, %u) ends at (%u, %u)", c0, f0,
				 c1, f1, c, f);
	}
	return n;
}

static void known_paths(void **state)
{
	struct sh2000_timing_step st[SH2000_TIMING_STEPS_MAX];

	(void)state;
	assert_int_equal(path(2000, 20, 2000, 20, SH2000_TIMING_NO_LONGER, st), 0);
	assert_int_equal(path(2000, 20, 2000, 10, SH2000_TIMING_NO_LONGER, st), 1);
	/* down: the coarse period first (50 us in between, not 200) */
	assert_int_equal(path(2000, 20, 1000, 10, SH2000_TIMING_NO_LONGER, st), 2);
	assert_int_equal(st[0].id, SH2000_GP_COARSE_PERIOD_US);
	/* up: the fine steps first */
	assert_int_equal(path(1000, 10, 2000, 20, SH2000_TIMING_NO_LONGER, st), 2);
	assert_int_equal(st[0].id, SH2000_GP_FINE_STEPS);
	/* neither order of two sets keeps 100 us: (100, 20) is 5 us, below
	 * the card's minimum, (2000, 1) is 2 ms */
	assert_true(path(2000, 20, 100, 1, SH2000_TIMING_NO_LONGER, st) > 2);
	assert_int_equal(path(2000, 20, 100, 1, 0, st), 2);
	/* (3000, 20) is 150 us and (2000, 30) not whole ns: through more */
	assert_true(path(2000, 20, 3000, 30, SH2000_TIMING_NO_LONGER, st) > 2);
	/* the coarse period not known (0): set first, legal with fine0 */
	assert_int_equal(path(0, 1, 1000, 10, 0, st), 2);
	assert_int_equal(st[0].id, SH2000_GP_COARSE_PERIOD_US);
	assert_int_equal(st[0].value, 1000);
	assert_int_equal(path(0, 1, 1000, 1, 0, st), 1);
	/* targets the card refuses */
	assert_int_equal(path(2000, 20, 1000, 3, 0, st), -SH2000_EPARAM);
	assert_int_equal(path(2000, 20, 50, 1, 0, st), -SH2000_EPARAM);
	assert_int_equal(path(2000, 20, 1000, 200, 0, st), -SH2000_EPARAM);
	assert_int_equal(sh2000_timing_path(2000, 20, 100, 1, SH2000_TIMING_NO_LONGER,
					    st, 2), -SH2000_EPARAM);
}

/* Every pair of a grid of legal states reaches every other. */
static void every_pair(void **state)
{
	static const unsigned int cs[] = { 100, 250, 1000, 1500, 2000, 3000,
					   4096, 10000, 100000 };
	static const unsigned int fs[] = { 1, 2, 3, 5, 8, 10, 16, 20, 30, 64,
					   100, 1000 };
	struct sh2000_timing_step st[SH2000_TIMING_STEPS_MAX];
	unsigned int pairs = 0, bounded = 0;

	(void)state;
	for (size_t a = 0; a < sizeof(cs) / sizeof(cs[0]); a++)
	for (size_t b = 0; b < sizeof(fs) / sizeof(fs[0]); b++)
	for (size_t c = 0; c < sizeof(cs) / sizeof(cs[0]); c++)
	for (size_t d = 0; d < sizeof(fs) / sizeof(fs[0]); d++) {
		if (!sh2000_timing_ok(cs[a], fs[b]) ||
		    !sh2000_timing_ok(cs[c], fs[d]))
			continue;
		pairs++;
		if (path(cs[a], fs[b], cs[c], fs[d], SH2000_TIMING_NO_LONGER,
			 st) >= 0)
			bounded++;
		else if (path(cs[a], fs[b], cs[c], fs[d], 0, st) < 0)
			fail_msg("(%u, %u) -> (%u, %u): no path", cs[a], fs[b],
				 cs[c], fs[d]);
	}
	print_message("%u pairs, %u of them within the longer servo period\n",
		      pairs, bounded);
	assert_true(bounded > pairs / 2);
}

static void get_timing(struct sh2000 *h, double *c, double *f)
{
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, c));
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, f));
}

static void on_the_card(void **state)
{
	struct sh2000 *h = simtest_open();
	double c, f;

	(void)state;
	CHECK(sh2000_set_timing(h, 1000, 10));
	get_timing(h, &c, &f);
	assert_true(c == 1000 && f == 10);
	CHECK(sh2000_set_timing(h, 100, 1));
	CHECK(sh2000_set_timing(h, 3000, 30));
	get_timing(h, &c, &f);
	assert_true(c == 3000 && f == 30);
	/* refused before anything is sent, with the reason */
	assert_int_equal(sh2000_set_timing(h, 1000, 3), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "whole number of ns"));
	assert_int_equal(sh2000_set_timing(h, 50, 1), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "coarse_period_us"));
	get_timing(h, &c, &f);
	assert_true(c == 3000 && f == 30);
	CHECK(sh2000_set_timing(h, 2000, 20));
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(known_paths),
		cmocka_unit_test(every_pair),
		cmocka_unit_test(on_the_card),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
