// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000's comp= (hal/comp.c) on the in-process card, no LinuxCNC:
 * a good table file is checked, loaded and shown (its identity, sum and
 * count, the card's status the same); a bad one is refused by the check
 * with the library's FILE:LINE message and the card's tables do not
 * change; "" and "-" are no table. Tables loaded and cleared later by
 * another program (a served card's second handle) show in what the servo
 * thread takes from the watch thread, which it never waits for; the
 * in-process card, which no other program reaches, has no watch. After a
 * load, each soft limit the tables move the tool beyond is said in the
 * library's words.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "hsc.h"
#include "sh2000/sim.h"

static char path[64];

static void write_file(const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

static void open_card(struct hsc_card *c)
{
	char msg[256];

	if (hsc_open(c, 0, "sim", msg, sizeof(msg)) < 0)
		fail_msg("hsc_open: %s", msg);
}

/* A card served in this process (sim:NAME), as another program reaches
 * it, and hal_sh2000's card on it. */
static struct sh2000_sim_server *serve_card(struct hsc_card *c, char *dev,
					    size_t len)
{
	struct sh2000_sim_server *s = NULL;
	char msg[256];

	snprintf(dev, len, "sim:hsc-comp-%d", (int)getpid());
	if (sh2000_sim_server_create(&s, dev + 4, NULL, 0, msg, sizeof(msg)) < 0 ||
	    sh2000_sim_server_start(s) < 0)
		fail_msg("server %s: %s", dev, msg);
	if (hsc_open(c, 0, dev, msg, sizeof(msg)) < 0)
		fail_msg("hsc_open %s: %s", dev, msg);
	return s;
}

static void wanted(void **state)
{
	(void)state;
	assert_false(hsc_comp_wanted(NULL));
	assert_false(hsc_comp_wanted(""));
	assert_false(hsc_comp_wanted("-"));
	assert_true(hsc_comp_wanted("mill.comp"));
}

static void good_table(void **state)
{
	struct sh2000_comp_status st;
	struct hsc_card c;
	char msg[512] = "";

	(void)state;
	write_file("id 0x12345678\npitch X\n0 0\n100 0.002\n200 0.001\n");
	open_card(&c);
	assert_int_equal(hsc_comp_check(&c, path, msg, sizeof(msg)), 0);
	/* the check sends nothing */
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	if (hsc_comp_load(&c, path, msg, sizeof(msg)) < 0)
		fail_msg("hsc_comp_load: %s", msg);
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_ACTIVE);
	assert_int_equal(c.comp.id, 0x12345678u);
	assert_int_equal(c.comp.tables, 1);
	assert_int_equal(c.comp.sum, st.sum);
	assert_int_not_equal(c.comp.sum, 0);
	hsc_close(&c);
}

static void bad_table(void **state)
{
	struct sh2000_comp_status st;
	struct hsc_card c;
	char msg[512] = "", want[128];

	(void)state;
	/* line 5: positions not increasing */
	write_file("id 0x1\npitch X\n0 0\n100 0.002\n50 0.001\n");
	open_card(&c);
	assert_true(hsc_comp_check(&c, path, msg, sizeof(msg)) < 0);
	snprintf(want, sizeof(want), "%s:5:", path);
	if (!strstr(msg, want))
		fail_msg("check's message '%s' lacks '%s'", msg, want);
	/* the loader refuses it the same way, and nothing changes */
	msg[0] = '\0';
	assert_true(hsc_comp_load(&c, path, msg, sizeof(msg)) < 0);
	if (!strstr(msg, want))
		fail_msg("load's message '%s' lacks '%s'", msg, want);
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	assert_int_equal(c.comp.sum, 0);
	/* a file that is not there: said */
	assert_true(hsc_comp_check(&c, "/nonexistent/mill.comp", msg,
				   sizeof(msg)) < 0);
	assert_non_null(strstr(msg, "/nonexistent/mill.comp"));
	hsc_close(&c);
}

/* The servo thread's take, every ms of wall time for up to 10 s, until
 * the card's tables are sum `sum`: 1 if they came. */
static int shows(struct hsc_card *c, uint32_t sum)
{
	const struct timespec ms = { 0, 1000000L };
	int i;

	for (i = 0; i < 10000; i++) {
		hsc_comp_take(c);
		if (c->comp.sum == sum)
			return 1;
		nanosleep(&ms, NULL);
	}
	return 0;
}

/* Loaded at start, then cleared and loaded again through the card (as
 * sh2000ctl comp would from another program): what the servo thread
 * takes follows within the watch's period, the card's status the same. */
/* What hsc_comp_reach() hands on: the words of each warning. */
struct said {
	unsigned int n;
	char words[4][512];
};

static void collect(void *ctx, const char *words)
{
	struct said *s = ctx;

	if (s->n < 4)
		snprintf(s->words[s->n], sizeof(s->words[0]), "%s", words);
	s->n++;
}

/* Load and judge the tables on card c: the warnings said. */
static struct said load_and_judge(struct hsc_card *c, const char *text)
{
	struct said s = { 0 };
	char msg[512] = "";
	int r;

	write_file(text);
	if (hsc_comp_load(c, path, msg, sizeof(msg)) < 0)
		fail_msg("hsc_comp_load: %s", msg);
	r = hsc_comp_reach(c, path, collect, &s, msg, sizeof(msg));
	if (r < 0)
		fail_msg("hsc_comp_reach: %s", msg);
	assert_int_equal(r, (int)s.n);
	return s;
}

/* comp= warns where the card's soft limit and the correction added after
 * it put the tool beyond the limit, in the library's words (the same as
 * sh2000ctl comp load's), and says nothing where it does not. */
static void reach_warned(void **state)
{
	const char *flat = "pitch X\n-100 0.5\n0 0.5\n100 0.5\n";
	struct hsc_card c;
	struct said s;
	char msg[512];

	(void)state;
	open_card(&c);
	/* no soft limits (the card's default): nothing to be beyond */
	s = load_and_judge(&c, flat);
	assert_int_equal(s.n, 0);
	/* soft_max 10: +0.5 mm there is beyond it; soft_min -10: -9.5 is not */
	assert_int_equal(sh2000_param_set(c.h, 0, SH2000_P_SOFT_MAX, 10.0), 0);
	assert_int_equal(sh2000_param_set(c.h, 0, SH2000_P_SOFT_MIN, -10.0), 0);
	s = load_and_judge(&c, flat);
	assert_int_equal(s.n, 1);
	assert_string_equal(s.words[0], "axis x at its soft_max 10.000000 mm: the tables put the tool up to 0.500000 mm beyond it (at 10.500000 mm): the card judges soft limits on nominal positions, then adds the correction");
	/* a correction that brings the tool inside at both limits */
	s = load_and_judge(&c, "pitch X\n-10 0.001\n0 0\n10 -0.001\n");
	assert_int_equal(s.n, 0);
	/* a file gone since the load: the library's message, no warning */
	s.n = 0;
	assert_true(hsc_comp_reach(&c, "/nonexistent/mill.comp", collect, &s,
				   msg, sizeof(msg)) < 0);
	assert_non_null(strstr(msg, "/nonexistent/mill.comp"));
	assert_int_equal(s.n, 0);
	hsc_close(&c);
}

static void watched(void **state)
{
	struct sh2000_comp_status st;
	struct hsc_card c;
	char msg[512] = "";
	uint32_t first;

	struct sh2000_sim_server *s;
	struct sh2000 *other = NULL;
	char dev[64];

	(void)state;
	write_file("id 0x12345678\npitch X\n0 0\n100 0.002\n200 0.001\n");
	s = serve_card(&c, dev, sizeof(dev));
	if (hsc_comp_load(&c, path, msg, sizeof(msg)) < 0)
		fail_msg("hsc_comp_load: %s", msg);
	first = c.comp.sum;
	assert_int_equal(hsc_comp_watch_start(&c, 20, msg, sizeof(msg)), 0);
	assert_int_equal(c.cw.started, 1);
	if (sh2000_open(&other, dev, msg, sizeof(msg)) < 0)
		fail_msg("open %s: %s", dev, msg);
	assert_int_equal(sh2000_comp_clear(other), 0);
	assert_true(shows(&c, 0));
	assert_int_equal(c.comp.tables, 0);
	assert_int_equal(c.comp.id, 0);
	write_file("id 0xabcd\npitch Y\n0 0\n100 0.001\n");
	if (sh2000_comp_load_file(other, path) < 0)
		fail_msg("load: %s", sh2000_last_error(other));
	assert_int_equal(sh2000_comp_status(other, &st), 0);
	assert_int_not_equal(st.sum, first);
	assert_true(shows(&c, st.sum));
	assert_int_equal(c.comp.id, 0xabcdu);
	assert_int_equal(c.comp.tables, 1);
	sh2000_close(other);
	hsc_close(&c);	/* stops the watch */
	assert_int_equal(c.cw.started, 0);
	sh2000_sim_server_destroy(s);
}

/* The in-process card is this module's handle's alone: no watch (it
 * would share the servo thread's handle), and the tables stay what the
 * load set. */
static void no_watch_in_process(void **state)
{
	struct hsc_card c;
	char msg[256];

	(void)state;
	open_card(&c);
	assert_int_equal(hsc_comp_watch_start(&c, 20, msg, sizeof(msg)), 0);
	assert_int_equal(c.cw.started, 0);
	hsc_comp_take(&c);
	hsc_close(&c);
}

/* The servo thread never waits for the watch: with the watch's lock
 * held, the take changes nothing and returns; freed, it takes. */
static void take_never_waits(void **state)
{
	const struct timespec ms = { 0, 1000000L };
	struct hsc_card c;
	char msg[256];
	int i;

	struct sh2000_sim_server *s;
	char dev[64];

	(void)state;
	s = serve_card(&c, dev, sizeof(dev));
	assert_int_equal(hsc_comp_watch_start(&c, 60000, msg, sizeof(msg)), 0);
	/* the watch's first read done, it sleeps for a minute (the stop cuts
	 * that short) */
	for (i = 0; i < 10000; i++) {
		pthread_mutex_lock(&c.cw.lock);
		if (c.cw.reads)
			break;
		pthread_mutex_unlock(&c.cw.lock);
		nanosleep(&ms, NULL);
	}
	assert_true(i < 10000);
	c.cw.seen.sum = 0x5eed;
	c.cw.fresh = 1;
	hsc_comp_take(&c);
	assert_int_equal(c.comp.sum, 0);
	pthread_mutex_unlock(&c.cw.lock);
	hsc_comp_take(&c);
	assert_int_equal(c.comp.sum, 0x5eed);
	hsc_close(&c);
	sh2000_sim_server_destroy(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(wanted),
		cmocka_unit_test(good_table),
		cmocka_unit_test(bad_table),
		cmocka_unit_test(reach_warned),
		cmocka_unit_test(watched),
		cmocka_unit_test(no_watch_in_process),
		cmocka_unit_test(take_never_waits),
	};
	int fd, r;

	snprintf(path, sizeof(path), "/tmp/test_hsc_comp_XXXXXX");
	fd = mkstemp(path);
	if (fd < 0)
		return 1;
	close(fd);
	r = cmocka_run_group_tests(tests, NULL, NULL);
	unlink(path);
	return r;
}
