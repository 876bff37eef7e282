// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * Compensation tables loaded at start (the module's comp= argument,
 * docs/linuxcnc.md "Compensation tables"): before the servo thread runs,
 * each card's table file goes through libsh2000's own loader, the one
 * sh2000ctl comp load uses, so the file's format, its checks and their
 * FILE:LINE messages have one owner. Not real-time: called from
 * rtapi_app_main only.
 *
 * Then the card's tables are watched: another program may load or clear
 * them later (sh2000ctl comp, at rest), and sh2000.N.comp-id, comp-sum and
 * comp-tables follow the card. Reading them is not a real-time call, so a
 * thread beside the servo thread reads them every HSC_COMP_WATCH_MS (8
 * words, some 10 port cycles) through a handle of its own, as another
 * program beside LinuxCNC would (sh2000ctl comp show; the in-process sim,
 * which no other program reaches, has no watch): it never holds the
 * servo thread's handle, whose calls would find it busy for as long as
 * this thread, which is no real-time one, is kept off the CPU. The servo
 * thread takes the result when the watch's lock is free (trylock, never
 * waits).
 *
 * After the load, each soft limit the tables move the tool beyond is
 * said (hsc_comp_reach(): the card judges soft limits on nominal
 * positions and adds the correction after; the library judges it).
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "hsc.h"

int hsc_comp_wanted(const char *path)
{
	return path && path[0] && strcmp(path, "-") != 0;
}

/* The file read and checked against the card's scales and limits by the
 * loader's own check (sh2000_comp_check_file): a bad table on any card
 * fails the load before any card's tables change. */
int hsc_comp_check(struct hsc_card *c, const char *path, char *msg, size_t len)
{
	int r = sh2000_comp_check_file(c->h, path);

	if (r < 0)
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
	return r;
}

int hsc_comp_load(struct hsc_card *c, const char *path, char *msg, size_t len)
{
	int r = sh2000_comp_load_file(c->h, path);

	if (r < 0) {
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
		return r;
	}
	r = sh2000_comp_status(c->h, &c->comp);
	if (r < 0)
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
	return r;
}

/* The tables' reach judged by the library, the one owner of the rule and
 * its words; this only hands each warning on. */
int hsc_comp_reach(struct hsc_card *c, const char *path,
		   void (*say)(void *ctx, const char *words), void *ctx,
		   char *msg, size_t len)
{
	struct sh2000_comp_reach reach[SH2000_AXES];
	struct sh2000_comp_window win;
	char words[512];
	int r = sh2000_comp_reach_file(c->h, path, &win, reach), n = 0;

	if (r < 0) {
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
		return r;
	}
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		for (unsigned int side = 0; side < 2u; side++)
			if (sh2000_comp_reach_warning(&win, reach, a, side, words,
						      sizeof(words)) > 0) {
				say(ctx, words);
				n++;
			}
	return n;
}

int hsc_comp_refresh(struct hsc_card *c)
{
	struct sh2000_comp_status st;
	int r = sh2000_comp_status(c->cw.h, &st);

	pthread_mutex_lock(&c->cw.lock);
	if (r == 0) {
		c->cw.seen = st;
		c->cw.fresh = 1;
	}
	c->cw.reads++;
	pthread_mutex_unlock(&c->cw.lock);
	return r;
}

/* Until stopped: a read, then period_ms of sleep that stop cuts short. A
 * card without tables in its protocol (-EOPNOTSUPP) is left alone, and so
 * is an io: card whose ports this thread may not use; any other failure
 * (a card gone for a while) is read again next period. */
static void *watch(void *arg)
{
	struct hsc_card *c = arg;
	struct timespec until;
	int stop = hsc_io_thread(c->device) < 0;

	while (!stop) {
		if (hsc_comp_refresh(c) == -EOPNOTSUPP)
			break;
		clock_gettime(CLOCK_MONOTONIC, &until);
		until.tv_sec += c->cw.period_ms / 1000u;
		until.tv_nsec += (long)(c->cw.period_ms % 1000u) * 1000000L;
		if (until.tv_nsec >= 1000000000L) {
			until.tv_sec++;
			until.tv_nsec -= 1000000000L;
		}
		pthread_mutex_lock(&c->cw.lock);
		while (!c->cw.stop &&
		       pthread_cond_timedwait(&c->cw.wake, &c->cw.lock, &until) == 0)
			;
		stop = c->cw.stop;
		pthread_mutex_unlock(&c->cw.lock);
	}
	return NULL;
}

/* The watch's own handle: the card opened again. */
static int watch_open(struct hsc_card *c, char *msg, size_t len)
{
	c->cw.h = NULL;
	return sh2000_open(&c->cw.h, c->device, msg, len);
}

int hsc_comp_watch_start(struct hsc_card *c, unsigned int period_ms,
			 char *msg, size_t len)
{
	pthread_condattr_t ca;
	int r;

	snprintf(msg, len, "the tables' watch: %s", strerror(EINVAL));
	if (c->cw.started || !period_ms)
		return -EINVAL;
	/* the in-process card is this handle's alone: no other program can
	 * change its tables, and a watch would have to share the servo
	 * thread's handle */
	if (!strcmp(c->device, "sim"))
		return 0;
	r = watch_open(c, msg, len);
	if (r < 0)
		return r;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	r = pthread_cond_init(&c->cw.wake, &ca);
	pthread_condattr_destroy(&ca);
	if (!r) {
		r = pthread_mutex_init(&c->cw.lock, NULL);
		if (r)
			pthread_cond_destroy(&c->cw.wake);
	}
	if (r)
		goto fail;
	c->cw.period_ms = period_ms;
	c->cw.stop = 0;
	c->cw.fresh = 0;
	c->cw.reads = 0;
	r = pthread_create(&c->cw.thread, NULL, watch, c);
	if (!r) {
		c->cw.started = 1;
		return 0;
	}
	pthread_mutex_destroy(&c->cw.lock);
	pthread_cond_destroy(&c->cw.wake);
fail:
	snprintf(msg, len, "the tables' watch: %s", strerror(r));
	sh2000_close(c->cw.h);
	c->cw.h = NULL;
	return -r;
}

void hsc_comp_watch_stop(struct hsc_card *c)
{
	if (!c->cw.started)
		return;
	pthread_mutex_lock(&c->cw.lock);
	c->cw.stop = 1;
	pthread_cond_signal(&c->cw.wake);
	pthread_mutex_unlock(&c->cw.lock);
	pthread_join(c->cw.thread, NULL);
	pthread_mutex_destroy(&c->cw.lock);
	pthread_cond_destroy(&c->cw.wake);
	sh2000_close(c->cw.h);
	c->cw.h = NULL;
	c->cw.started = 0;
}

void hsc_comp_take(struct hsc_card *c)
{
	if (!c->cw.started || pthread_mutex_trylock(&c->cw.lock))
		return;
	if (c->cw.fresh) {
		c->comp = c->cw.seen;
		c->cw.fresh = 0;
	}
	pthread_mutex_unlock(&c->cw.lock);
}
