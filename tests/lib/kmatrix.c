// SPDX-License-Identifier: MIT
/*
 * sh2000-kmatrix HOST DSP [BOUND_MS]: the card faults of the fault matrix
 * (docs/faults.md) through the kernel driver, for the VM suite
 * (tests/kernel: HOST /dev/sh2000-0, DSP /dev/sh2000-dsp-0 of a
 * sh2000_sim card). The card model runs on the mmapped DSP side in a
 * thread of this program (as sh2000-sim --attach does, at SCHED_FIFO like
 * the DSP it stands for), so that the program can inject its faults; the
 * host side is libsh2000 on HOST.
 *
 * Each fault, at idle (enabled, polled every 1 ms) and while a run streams
 * (libsh2000-motion's runner, a 400 mm line along X at 100 mm/s, the fault
 * after 150 records, as lib_matrix does): the host learns the fault's
 * error within BOUND_MS (default 1000) and its message names the fault
 * (protocol 1.4's first-fault record), the card's set-point comes to rest
 * (and the carriage, but after a DSP stall, whose DAC holds), sh2000_reset
 * and enable bring it back, and the next run works. The bound is generous
 * on purpose: the VM runs under -icount on one vCPU, and the millisecond
 * figures are lib_matrix's; the times measured are printed.
 *
 * Prints "ok ...", "FAIL ..." and "info ..." lines (tests/kernel/init
 * turns them into KTEST lines); exit status 1 if any check failed, 2 if
 * the card could not be set up. No cmocka: it has no static library, and
 * this program is linked -static for the VM's initramfs, which is also
 * why it does not use tests/lib/served.c (built on cmocka's fail_msg).
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <sched.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000/sim.h"
#include "sh2000/run.h"
#include "sh2000_hw.h"
#include "host_halt.h"

#define FEED		100.0	/* mm/s along X */
#define AT_POINT	150u	/* records streamed before the fault */
#define QUIET_MS	100u	/* an idle host watches a silent fault */
#define SETTLE_MS	50u	/* after the host's answer, before the rest check */
#define REST_MS		20u	/* the span the card must keep still over */
#define SCALE		1e5	/* counts/mm */

enum activity { ACT_IDLE, ACT_RUN, ACTS };

static const char *const act_name[ACTS] = { "idle", "run" };

struct fault {
	const char *name;
	enum sh2000_inject what;
	int code[ACTS];		/* the error the host learns (0: none) */
	const char *named;	/* what its message says */
};

/* The host's errors are lib_matrix's (test_matrix.c), the names the
 * library's messages (status.c). */
static const struct fault faults[] = {
	{ "limit switch", SH2000_INJECT_LIMIT,
	  { -SH2000_EHARD_LIMIT, -SH2000_EHARD_LIMIT }, "limit switch" },
	{ "axis jam", SH2000_INJECT_JAM, { 0, -SH2000_EFERR },
	  "following error limit" },
	{ "counter glitch", SH2000_INJECT_COUNTER_GLITCH,
	  { -SH2000_ECOUNTER, -SH2000_ECOUNTER }, "counter fault" },
	{ "DSP stall", SH2000_INJECT_DSP_STALL,
	  { -SH2000_EHEARTBEAT, -SH2000_EHEARTBEAT }, "heartbeat stuck" },
	{ "heartbeat stop", SH2000_INJECT_HEARTBEAT_STOP,
	  { -SH2000_EHEARTBEAT, -SH2000_EHEARTBEAT }, "heartbeat stuck" },
	{ "RAM word flip", SH2000_INJECT_RAM_FLIP,
	  { -SH2000_EMAGIC, -SH2000_EREJECTED }, NULL },
	{ "segment drop", SH2000_INJECT_DROP_SEGMENT,
	  { 0, -SH2000_EREJECTED }, "record dropped" },
};

#define NFAULTS (sizeof(faults) / sizeof(faults[0]))

struct cell {
	struct sh2000 *h;
	struct sh2000_sim_server *s;
	const struct fault *f;
	enum activity act;
	int injected, inject_err, code;
	double t_inject, t_learnt;
	char msg[300];
};

static int failed;
static double bound_ms = 1000.0;

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static void sleep_ms(unsigned int ms)
{
	struct timespec ts = { ms / 1000u, (long)(ms % 1000u) * 1000000L };

	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

/* The name the message must carry: a RAM flip at rest hits MAGIC. */
static const char *named(const struct fault *f, enum activity a)
{
	if (f->what == SH2000_INJECT_RAM_FLIP)
		return a == ACT_IDLE ? "magic word" : "bad record checksum";
	return f->named;
}

/* The injection, with the word a RAM flip hits: the record pushed last
 * while streaming (its first position word), MAGIC at rest; the + limit
 * switch of X. */
static void inject(struct cell *c)
{
	unsigned int arg = 0;

	if (c->f->what == SH2000_INJECT_RAM_FLIP && c->act == ACT_RUN)
		arg = SH2000_W_RING_BASE +
		      (unsigned int)((sh2000_next_segment(c->h) - 1) %
				     SH2000_RING_RECORDS) * SH2000_RECORD_WORDS +
		      SH2000_REC_POS_LO(0);
	else if (c->f->what == SH2000_INJECT_RAM_FLIP)
		arg = SH2000_W_MAGIC;
	else if (c->f->what == SH2000_INJECT_LIMIT)
		arg = 1;
	c->t_inject = now_ms();
	c->injected = 1;
	c->inject_err = sh2000_sim_server_inject(c->s, c->f->what, 0, arg);
}

static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct cell *c = ctx;

	if (!c->injected && p->points >= AT_POINT)
		inject(c);
}

/* A line along X from where the card is, by dx mm; the run's error (its
 * message in msg). */
static int run_line(struct sh2000 *h, double dx, struct cell *c, char *msg,
		    size_t len)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_status st;
	struct sh2000_run *r;
	double b[SH2000_AXES];
	unsigned int a;
	int e = sh2000_poll(h, &st);

	if (!e)
		e = sh2000_run_path_config(h, &pc);
	if (e) {
		snprintf(msg, len, "%s", sh2000_last_error(h));
		return e;
	}
	for (a = 0; a < SH2000_AXES; a++)
		b[a] = st.axis[a].cmd_mm;
	b[0] += dx;
	sh2000_run_config_default(&rc);
	if (c) {
		rc.progress = on_progress;
		rc.ctx = c;
	}
	e = sh2000_run_create(&r, h, &pc, &rc, msg, len);
	if (e < 0)
		return e;
	e = sh2000_path_line(sh2000_run_path(r), b, FEED);
	if (!e)
		e = sh2000_run_finish(r);
	snprintf(msg, len, "%s", e ? sh2000_run_error(r) : "");
	sh2000_run_destroy(r);
	return e;
}

/* Idle: inject, then poll every 1 ms until the host sees an error (or,
 * for a fault that says nothing at rest, QUIET_MS passed). */
static void act_idle(struct cell *c)
{
	double limit = c->f->code[ACT_IDLE] ? bound_ms : QUIET_MS;
	struct sh2000_status st;
	int e;

	inject(c);
	do {
		e = sh2000_poll(c->h, &st);
		if (!e)
			e = sh2000_status_error(c->h, &st);
		if (!e)
			sleep_ms(1);
	} while (!e && now_ms() - c->t_inject < limit);
	c->t_learnt = now_ms();
	c->code = e;
	snprintf(c->msg, sizeof(c->msg), "%s", e ? sh2000_last_error(c->h) : "");
	if (e)
		host_halt(c->h);
}

static void act_run(struct cell *c)
{
	c->code = run_line(c->h, 400.0, c, c->msg, sizeof(c->msg));
	c->t_learnt = now_ms();
}

/*
 * The card at rest SETTLE_MS after the host's answer: not running, and
 * over REST_MS each axis' set-point still, or the axis no longer driven
 * (DAC 0: the card disabled it on an axis fault, and its carriage coasts
 * on its friction, docs/faults.md). A stalled DSP's state and set-point
 * are frozen (its DAC holds: nothing on the card can stop the carriage).
 * 0, or -1 with what moved in why; what coasts is in why either way.
 */
static int at_rest(struct cell *c, char *why, size_t len)
{
	struct sh2000_probe p0, p1;
	unsigned int a;
	size_t n = 0;

	why[0] = '\0';
	sleep_ms(SETTLE_MS);
	sh2000_sim_server_probe(c->s, &p0);
	sleep_ms(REST_MS);
	sh2000_sim_server_probe(c->s, &p1);
	if (p1.state == SH2000_STATE_RUNNING &&
	    c->f->what != SH2000_INJECT_DSP_STALL) {
		snprintf(why, len, "card state running");
		return -1;
	}
	for (a = 0; a < SH2000_AXES; a++) {
		double dc = fabs(p1.axis[a].fine_cmd - p0.axis[a].fine_cmd);
		double v = fabs(p1.axis[a].actual - p0.axis[a].actual) /
			   SCALE / (REST_MS * 1e-3);

		if (dc > 0.5 && (p0.axis[a].dac || p1.axis[a].dac)) {
			snprintf(why, len,
				 "axis %u's set-point moved %.0f counts in %u ms, DAC %d",
				 a, dc, REST_MS, p1.axis[a].dac);
			return -1;
		}
		/* above 1 mm/s: coasting, not the servo settling */
		if (v > 1.0 && n < len)
			n += (size_t)snprintf(why + n, len - n,
					      "%saxis %u's carriage coasting at %.1f mm/s (DAC %d%s)",
					      n ? ", " : "", a, v, p1.axis[a].dac,
					      p1.axis[a].dac ? ", held" : ": not driven");
	}
	return 0;
}

/* Clear the injection (a lost MAGIC is flipped back: the firmware writes
 * it at boot only, and the flip again stands for a reload), reset, enable,
 * and a 2 mm run back along X. 0, or the error with msg. */
static int recover(struct cell *c, char *msg, size_t len)
{
	struct sh2000_status st;
	int e;

	sh2000_sim_server_inject(c->s, SH2000_INJECT_CLEAR, 0, 0);
	if (c->code == -SH2000_EMAGIC)
		sh2000_sim_server_inject(c->s, SH2000_INJECT_RAM_FLIP, 0,
					 SH2000_W_MAGIC);
	/* a stalled DSP acts on the host's emergency stop when it runs again */
	sleep_ms(SETTLE_MS);
	e = sh2000_reset(c->h);
	if (!e)
		e = sh2000_enable(c->h, 0xf);
	if (!e)
		e = sh2000_poll(c->h, &st);
	if (!e)
		e = sh2000_status_error(c->h, &st);
	if (e) {
		snprintf(msg, len, "reset + enable: %s", sh2000_last_error(c->h));
		return e;
	}
	return run_line(c->h, -2.0, NULL, msg, len);
}

static void check(int ok, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void check(int ok, const char *fmt, ...)
{
	va_list ap;

	printf("%s kmatrix: ", ok ? "ok" : "FAIL");
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	printf("\n");
	failed |= !ok;
}

/* What the host learnt: the expected error within the bound, named. */
static void check_learnt(const struct cell *c)
{
	const char *want = named(c->f, c->act);
	int want_code = c->f->code[c->act];
	double ms = c->t_learnt - c->t_inject;
	int ok;

	if (!c->injected || c->inject_err) {
		check(0, "%s %s: not injected (%d), the host learnt %d \"%s\"",
		      c->f->name, act_name[c->act], c->inject_err, c->code,
		      c->msg);
		return;
	}
	if (!want_code) {
		check(!c->code, "%s %s: nothing reported in %.0f ms%s%s",
		      c->f->name, act_name[c->act], ms,
		      c->code ? ", but: " : "", c->msg);
		return;
	}
	ok = c->code == want_code && ms <= bound_ms && strstr(c->msg, want);
	if (ok)
		check(1, "%s %s: detected in %.1f ms, named \"%s\"",
		      c->f->name, act_name[c->act], ms, c->msg);
	else
		check(0, "%s %s: detected in %.1f ms, named \"%s\" (%s; want %s within %.0f ms, naming \"%s\")",
		      c->f->name, act_name[c->act], ms, c->msg,
		      sh2000_strerror(c->code), sh2000_strerror(want_code),
		      bound_ms, want);
}

static void run_cell(struct sh2000 *h, struct sh2000_sim_server *s,
		     const struct fault *f, enum activity a)
{
	struct cell c = { .h = h, .s = s, .f = f, .act = a };
	char why[300];
	int e;

	e = sh2000_enable(h, 0xf);
	if (e) {
		check(0, "%s %s: enable before the fault: %s", f->name,
		      act_name[a], sh2000_last_error(h));
		return;
	}
	if (a == ACT_IDLE)
		act_idle(&c);
	else
		act_run(&c);
	check_learnt(&c);
	e = at_rest(&c, why, sizeof(why));
	check(!e, "%s %s: the card comes to rest%s%s", f->name, act_name[a],
	      why[0] ? ": " : "", why);
	e = recover(&c, why, sizeof(why));
	check(!e, "%s %s: reset + enable bring it back, the next run works%s%s",
	      f->name, act_name[a], e ? ": " : "", e ? why : "");
}

/* The DSP side of the card mapped (one page, MAP_SHARED only, as
 * sh2000-sim --attach maps it), NULL with a message. */
static uint16_t *map_dsp(const char *path, size_t *maplen)
{
	long page = sysconf(_SC_PAGESIZE);
	uint16_t *ram;
	int fd;

	*maplen = page > 0 ? (size_t)page : 4096;
	if (*maplen < SH2000_RAM_BYTES)
		*maplen = SH2000_RAM_BYTES;
	fd = open(path, O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		printf("FAIL kmatrix: %s: cannot open: %s\n", path,
		       strerror(errno));
		return NULL;
	}
	ram = mmap(NULL, *maplen, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	close(fd);
	if (ram == MAP_FAILED) {
		printf("FAIL kmatrix: %s: mmap of %zu bytes: %s\n", path,
		       *maplen, strerror(errno));
		return NULL;
	}
	return ram;
}

/* The card model in a thread of its own at SCHED_FIFO 50 (the thread
 * inherits the policy of this one): the DSP it stands for is never
 * delayed by a host program. This one, the host that streams, then goes
 * down to SCHED_FIFO 40, as a machine's motion host runs (below the
 * card, above everything else): on the one emulated CPU of the VM suite
 * a host at SCHED_OTHER let the ring run dry once the card model's
 * servo took more of that CPU. */
static struct sh2000_sim_server *start_model(uint16_t *ram, const char *path)
{
	const struct sched_param fifo = { .sched_priority = 50 },
				 host = { .sched_priority = 40 };
	struct sh2000_sim_server *s = NULL;
	char msg[256] = "";
	int rt = sched_setscheduler(0, SCHED_FIFO, &fifo) == 0;

	if (!rt)
		printf("info kmatrix: the card model not at SCHED_FIFO: %s\n",
		       strerror(errno));
	if (sh2000_sim_server_attach(&s, ram, NULL, 0, msg, sizeof(msg)) < 0 ||
	    sh2000_sim_server_start(s) < 0) {
		printf("FAIL kmatrix: card model on %s: %s\n", path, msg);
		sh2000_sim_server_destroy(s);
		s = NULL;
	}
	if (rt)
		sched_setscheduler(0, SCHED_FIFO, &host);
	return s;
}

/* The host side; a model just started may not have run its first cycle
 * (magic word, heartbeat): tried again for 1 s. */
static struct sh2000 *open_host(const char *dev)
{
	struct sh2000 *h = NULL;
	char msg[256];
	int r, tries = 0;

	while ((r = sh2000_open(&h, dev, msg, sizeof(msg))) < 0 &&
	       (r == -SH2000_EHEARTBEAT || r == -SH2000_EMAGIC) && ++tries < 20)
		sleep_ms(50);
	if (r < 0) {
		printf("FAIL kmatrix: open %s: %s\n", dev, msg);
		return NULL;
	}
	return h;
}

int main(int argc, char **argv)
{
	struct sh2000_sim_server *s;
	struct sh2000 *h = NULL;
	unsigned int fi;
	size_t maplen;
	uint16_t *ram;
	double t0;

	if (argc != 3 && argc != 4) {
		fprintf(stderr, "usage: sh2000-kmatrix HOST DSP [BOUND_MS]\n");
		return 2;
	}
	if (argc == 4)
		bound_ms = strtod(argv[3], NULL);
	setvbuf(stdout, NULL, _IOLBF, 0);
	ram = map_dsp(argv[2], &maplen);
	if (!ram)
		return 2;
	s = start_model(ram, argv[2]);
	if (s)
		h = open_host(argv[1]);
	if (!h) {
		sh2000_sim_server_destroy(s);
		munmap(ram, maplen);
		return 2;
	}
	t0 = now_ms();
	for (fi = 0; fi < NFAULTS; fi++) {
		run_cell(h, s, &faults[fi], ACT_IDLE);
		run_cell(h, s, &faults[fi], ACT_RUN);
	}
	printf("info kmatrix: %zu faults x idle, run in %.1f s, %llu servo cycles of the card model\n",
	       NFAULTS, (now_ms() - t0) / 1e3,
	       (unsigned long long)sh2000_sim_server_cycles(s));
	sh2000_disable(h, 0xf);
	sh2000_close(h);
	sh2000_sim_server_destroy(s);
	munmap(ram, maplen);
	return failed;
}
