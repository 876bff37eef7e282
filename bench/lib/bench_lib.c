/* SPDX-License-Identifier: MIT */
/*
 * libsh2000 figures, printed as a table (not a timed test):
 *  - port cycles per status poll, per segment record (by batch size), per
 *    command and per emergency stop, as the card model's FPGA counted them,
 *    and per real-time tick (sh2000_poll_once + one sh2000_push_point,
 *    through the point mailbox of protocol 1.3);
 *  - host CPU time per segment: the library alone (its thread, against a
 *    card served by another thread over shared memory, real time; the
 *    pushes alone and with the 100 us polling of the waits) and the
 *    library plus the in-process card model (`sim`);
 *  - simulated seconds per wall-clock second of `sim`.
 * Usage: bench_lib [points]   (default 20000)
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000/sim.h"

static double secs(clockid_t id)
{
	struct timespec ts;

	clock_gettime(id, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static uint64_t cycles(struct sh2000 *h)
{
	struct sh2000_port_counters c;

	sh2000_port_counters(h, &c);
	return c.clears + c.increments + c.data_reads + c.data_writes;
}

static void die(struct sh2000 *h, const char *what, int r)
{
	fprintf(stderr, "bench_lib: %s: %s (%s)\n", what, sh2000_strerror(r),
		h ? sh2000_last_error(h) : "");
	exit(1);
}

#define TRY(h, call) do { int r_ = (call); if (r_ < 0) die(h, #call, r_); } while (0)

/* Port cycles of one tick of a real-time thread streaming one point per
 * coarse period: sh2000_poll_once and sh2000_push_point (a batch of 4
 * through the ring first, as hal_sh2000 starts), over `ticks` ticks. */
static double tick_cost(struct sh2000 *h, unsigned int ticks, int32_t step)
{
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	uint64_t c0, t;
	unsigned int i, a;

	TRY(h, sh2000_poll(h, &st));
	for (a = 0; a < SH2000_AXES; a++)
		p[a] = st.axis[a].cmd_counts;
	for (i = 0; i < 4; i++) {
		p[0] += step;
		TRY(h, sh2000_push_point(h, p, 0));
	}
	c0 = cycles(h);
	t = sh2000_now_ns(h);
	for (i = 0; i < ticks; i++) {
		int r;

		t += 500000;	/* the thread's period: the coarse period */
		if (sh2000_now_ns(h) < t)
			sh2000_sleep_ns(h, t - sh2000_now_ns(h));
		r = sh2000_poll_once(h, &st);
		if (r < 0 && r != -EAGAIN)
			die(h, "sh2000_poll_once", r);
		p[0] += step;
		r = sh2000_push_point(h, p, i + 1 == ticks ? SH2000_PUSH_END : 0);
		if (r == -EAGAIN)
			p[0] -= step;	/* pushed again next tick */
		else if (r < 0)
			die(h, "sh2000_push_point", r);
	}
	c0 = cycles(h) - c0;
	TRY(h, sh2000_wait_idle(h, 10000));
	return (double)c0 / ticks;
}

/* Stream n points of a slow line on axis 0 in batches; returns the
 * thread CPU seconds spent inside the pushes alone. */
static double stream(struct sh2000 *h, unsigned int n, unsigned int batch,
		     int32_t step)
{
	double push_cpu = 0, c0;
	int32_t pts[SH2000_RING_RECORDS][SH2000_AXES];
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	unsigned int done = 0, i, a;

	TRY(h, sh2000_poll(h, &st));
	for (a = 0; a < SH2000_AXES; a++)
		p[a] = st.axis[a].cmd_counts;
	while (done < n) {
		unsigned int k = n - done < batch ? n - done : batch;

		TRY(h, sh2000_wait_space(h, k, 10000));
		for (i = 0; i < k; i++) {
			p[0] += step;
			memcpy(pts[i], p, sizeof(p));
		}
		c0 = secs(CLOCK_THREAD_CPUTIME_ID);
		TRY(h, sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])pts,
					  k, done + k == n ? SH2000_PUSH_END : 0));
		push_cpu += secs(CLOCK_THREAD_CPUTIME_ID) - c0;
		done += k;
	}
	TRY(h, sh2000_wait_idle(h, 60000));
	return push_cpu;
}

/* Port cycles of the pushes alone: wait for room, then count the push. */
static double record_cost(struct sh2000 *h, unsigned int batch,
			  unsigned int batches)
{
	int32_t pts[SH2000_RING_RECORDS][SH2000_AXES];
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	uint64_t sum = 0, c0;
	unsigned int b, i, a;

	TRY(h, sh2000_poll(h, &st));
	for (a = 0; a < SH2000_AXES; a++)
		p[a] = st.axis[a].cmd_counts;
	for (b = 0; b < batches; b++) {
		TRY(h, sh2000_wait_space(h, batch, 10000));
		for (i = 0; i < batch; i++) {
			p[0] += 100;
			memcpy(pts[i], p, sizeof(p));
		}
		c0 = cycles(h);
		/* each batch a motion of its own: waiting for room for 64
		 * means an empty ring, and writing 64 records takes longer
		 * than the card's last coarse period (an underrun) */
		TRY(h, sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])pts,
					  batch, SH2000_PUSH_END));
		sum += cycles(h) - c0;
	}
	TRY(h, sh2000_wait_idle(h, 60000));
	return (double)sum / ((double)batch * batches);
}

int main(int argc, char **argv)
{
	unsigned int n = argc > 1 ? (unsigned int)atoi(argv[1]) : 20000;
	struct sh2000 *h;
	char msg[256], name[64], dev[80];
	uint64_t c0, t0, t1;
	double w0, w1, cpu0, cpu1, push;
	int32_t v;
	unsigned int i, batches[] = { 1, 4, 16, 64 };
	struct sh2000_sim_server *srv;

	if (sh2000_open(&h, "sim", msg, sizeof(msg)) < 0) {
		fprintf(stderr, "bench_lib: %s\n", msg);
		return 1;
	}
	TRY(h, sh2000_enable(h, 0xf));
	printf("%-46s %12s\n", "libsh2000 on `sim` (port cycles ~ 1 us each)", "value");
	printf("%-46s %12s\n", "----------------------------------------------", "------------");

	TRY(h, sh2000_poll(h, NULL));
	c0 = cycles(h);
	for (i = 0; i < 1000; i++)
		TRY(h, sh2000_poll(h, NULL));
	printf("%-46s %12.1f\n", "port cycles per status poll (incl. re-reads)",
	       (cycles(h) - c0) / 1000.0);

	for (i = 0; i < sizeof(batches) / sizeof(batches[0]); i++) {
		char label[64];

		snprintf(label, sizeof(label), "port cycles per record, batches of %u",
			 batches[i]);
		printf("%-46s %12.1f\n", label,
		       record_cost(h, batches[i], 2048 / batches[i]));
	}

	c0 = cycles(h);
	for (i = 0; i < 1000; i++)
		TRY(h, sh2000_nop(h));
	printf("%-46s %12.1f\n", "port cycles per command (nop, incl. waiting)",
	       (cycles(h) - c0) / 1000.0);
	c0 = cycles(h);
	for (i = 0; i < 1000; i++)
		TRY(h, sh2000_command(h, SH2000_CMD_GET_PARAM, 0, SH2000_P_KP, 0, &v));
	printf("%-46s %12.1f\n", "port cycles per command (get_param)",
	       (cycles(h) - c0) / 1000.0);
	c0 = cycles(h);
	TRY(h, sh2000_estop(h, 10));
	printf("%-46s %12llu\n", "port cycles per emergency stop (to ACK)",
	       (unsigned long long)(cycles(h) - c0));
	TRY(h, sh2000_reset(h));
	TRY(h, sh2000_enable(h, 0xf));

	/* throughput of `sim`: library + card model */
	TRY(h, sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, 5));
	TRY(h, sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, 500));
	TRY(h, sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_STATUS_PERIOD, 6));
	printf("%-46s %12.1f\n", "port cycles per real-time tick (poll + point)",
	       tick_cost(h, 2000, 100));
	t0 = sh2000_now_ns(h);
	w0 = secs(CLOCK_MONOTONIC);
	cpu0 = secs(CLOCK_PROCESS_CPUTIME_ID);
	(void)stream(h, n, 32, 100);
	cpu1 = secs(CLOCK_PROCESS_CPUTIME_ID);
	w1 = secs(CLOCK_MONOTONIC);
	t1 = sh2000_now_ns(h);
	printf("%-46s %12.2f\n", "host CPU us per segment, library + card model",
	       (cpu1 - cpu0) * 1e6 / n);
	printf("%-46s %12.0f\n", "simulated s per wall-clock s (`sim`)",
	       (t1 - t0) * 1e-9 / (w1 - w0));
	printf("%-46s %12.2f\n", "  (simulated seconds in that run)", (t1 - t0) * 1e-9);
	sh2000_close(h);

	/* the library alone: its own thread against a served card */
	snprintf(name, sizeof(name), "bench-%d", (int)getpid());
	if (sh2000_sim_server_create(&srv, name, NULL, 0, msg, sizeof(msg)) < 0 ||
	    sh2000_sim_server_start(srv) < 0) {
		fprintf(stderr, "bench_lib: %s\n", msg);
		return 1;
	}
	snprintf(dev, sizeof(dev), "sim:%s", name);
	if (sh2000_open(&h, dev, msg, sizeof(msg)) < 0) {
		fprintf(stderr, "bench_lib: %s\n", msg);
		sh2000_sim_server_destroy(srv);
		return 1;
	}
	sh2000_set_heartbeat_limit(h, 500000000ull);
	TRY(h, sh2000_enable(h, 0xf));
	/* 500 us coarse period: 2000 points are a second of real time, with
	 * 16 ms queued behind the card (a loaded machine must keep up) */
	TRY(h, sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, 5));
	TRY(h, sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, 500));
	cpu0 = secs(CLOCK_THREAD_CPUTIME_ID);
	w0 = secs(CLOCK_MONOTONIC);
	push = stream(h, 2000, 32, 100);
	w1 = secs(CLOCK_MONOTONIC);
	cpu1 = secs(CLOCK_THREAD_CPUTIME_ID);
	printf("%-46s %12.2f\n", "host CPU us per segment, push alone (shm)",
	       push * 1e6 / 2000);
	printf("%-46s %12.2f\n", "host CPU us per segment, waits included (shm)",
	       (cpu1 - cpu0) * 1e6 / 2000);
	printf("%-46s %12.2f\n", "  (wall s for 2000 x 500 us segments)", w1 - w0);
	sh2000_close(h);
	sh2000_sim_server_destroy(srv);
	return 0;
}
