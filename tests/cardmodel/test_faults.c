// SPDX-License-Identifier: MIT
/* Underrun, emergency stop, host timeout, reset. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

#define MAXPTS 4000
static int32_t pts[MAXPTS][SH2000_AXES];
static double xs[MAXPTS];

static unsigned int long_move(void)
{
	unsigned int n = h_trapezoid(0, 2e7, 3e7, 3e8, 0.002, xs, MAXPTS), i;

	for (i = 0; i < n; i++) {
		pts[i][0] = (int32_t)lrint(xs[i]);
		pts[i][1] = (int32_t)lrint(-xs[i] / 3);
		pts[i][2] = pts[i][3] = 0;
	}
	return n;
}

/* Pushes the first m points (no END), keeping the ring topped up. */
static void stream_some(struct harness *h, unsigned int m, unsigned int *next,
			unsigned int cycles)
{
	while (cycles--) {
		while (*next < m && !h_push(h, pts[*next], (uint16_t)*next, 0))
			(*next)++;
		h_cycles(h, 1);
	}
}

static void underrun(void **state)
{
	struct harness *h = *state;
	unsigned int next = 0, i, start = 0, a;
	double T = 1e-4, amax = 5e8;

	long_move();
	h_trace(h, 100000);
	stream_some(h, 150, &next, 150 * 20 + 2);	/* runs dry */
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_UNDERRUN);
	h_cycles(h, 3000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	for (i = 0; i < h->trace_len; i++)
		if (h->trace[i].state == SH2000_STATE_STOPPING) {
			start = i;
			break;
		}
	assert_true(start > 0);
	for (a = 0; a < 2; a++) {
		double last = pts[149][a], vmax_seen = 0.0;

		for (i = start - 2; i + 2 < h->trace_len; i++) {
			const double *x0 = &h->trace[i].axis[a].fine_cmd;
			double x1 = h->trace[i + 1].axis[a].fine_cmd;
			double x2 = h->trace[i + 2].axis[a].fine_cmd;
			double acc = (x2 - 2 * x1 + *x0) / (T * T);

			assert_true(fabs(acc) <= amax * 1.05);
			if (fabs(x2 - x1) / T > vmax_seen)
				vmax_seen = fabs(x2 - x1) / T;
		}
		/* stopped, and not far beyond the last point: v^2 / 2a */
		assert_true(h->trace[h->trace_len - 1].axis[a].fine_cmd ==
			    h->trace[h->trace_len - 2].axis[a].fine_cmd);
		assert_true(fabs(h->trace[h->trace_len - 1].axis[a].fine_cmd - last) <
			    3e7 * 3e7 / (2 * amax) + 1000);
		(void)vmax_seen;
	}
	for (i = start; i < h->trace_len && h->trace[i].state == SH2000_STATE_STOPPING; i++)
		;
	printf("# underrun at 300 mm/s: stopped %.3f mm past the last record, decelerating for %.1f ms\n",
	       (h->trace[h->trace_len - 1].axis[0].fine_cmd - pts[149][0]) / 1e5,
	       0.1 * (i - start + 1));
}

static void estop_latency(void **state)
{
	struct harness *h = *state;
	unsigned int next = 0, i;
	const struct sh2000_probe *p;
	double frozen, over = 0.0;

	long_move();
	h_trace(h, 100000);
	stream_some(h, 400, &next, 1000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_RUNNING);
	assert_true(h_fill(h) > 0);
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 7);
	/* a command and records are queued too: the estop comes first */
	h_cmd_post(h, SH2000_CMD_NOP, 0, 0, 0);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_ESTOP_ACK), 7);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_ESTOP);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_ESTOP);
	assert_int_equal(h_fill(h), 0);
	p = &h->trace[h->trace_len - 1];
	frozen = p->axis[0].fine_cmd;
	/* the set-point froze at the actual position sampled in that cycle */
	assert_true(frozen == p->axis[0].actual);
	h_cycles(h, 500);
	for (i = h->trace_len - 500; i < h->trace_len; i++)
		assert_true(h->trace[i].axis[0].fine_cmd == frozen);
	/* braking from speed to the frozen point latches no axis fault */
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(0)), 0);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), SH2000_FAULT_ESTOP);
	for (i = h->trace_len - 500; i < h->trace_len; i++)
		if (h->trace[i].axis[0].actual - frozen > over)
			over = h->trace[i].axis[0].actual - frozen;
	printf("# estop at %.0f mm/s: braked to rest %.3f mm past the frozen point, back within %.0f counts after 50 ms\n",
	       p->axis[0].velocity / 1e5, over / 1e5,
	       fabs(h->trace[h->trace_len - 1].axis[0].actual - frozen));
	/* no record is consumed while in ESTOP; pushing one is rejected */
	h_push(h, pts[next], 999, 0);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), 999);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), SH2000_REJECT_STATE);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_ESTOP);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
}

static void host_timeout(void **state)
{
	struct harness *h = *state;
	unsigned int next = 0, n = 0;

	long_move();
	stream_some(h, 3000, &next, 200);
	h->host_alive = 0;
	while (!(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_HOST_TIMEOUT) && n < 5000) {
		while (next < 3000 && !h_push(h, pts[next], (uint16_t)next, 0))
			next++;
		h_cycles(h, 1);
		n++;
	}
	/* 100 ms = 1000 servo cycles of 100 us */
	assert_int_equal(n, 1000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_STOPPING);
	assert_int_equal(h_fill(h), 0);
	h_cycles(h, 3000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	/* an idle card does not time out */
	h->host_alive = 1;
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	h->host_alive = 0;
	h_cycles(h, 3000);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
}

static void protocol_fault(void **state)
{
	struct harness *h = *state;

	sh2000_dpram_write(h->ram, SH2000_W_HEAD, SH2000_RING_RECORDS + 1);
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_PROTOCOL);
	assert_int_equal(h_word(h, SH2000_W_TAIL), SH2000_RING_RECORDS + 1);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(underrun, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(estop_latency, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(host_timeout, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(protocol_fault, h_setup_enabled, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
