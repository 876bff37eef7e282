// SPDX-License-Identifier: MIT
/* The versioned snapshot: published every STATUS_PERIOD cycles, BEGIN and
 * END equal between publications, the body matching the card. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static void period(void **state)
{
	struct harness h;
	uint16_t s0;
	unsigned int i;

	(void)state;
	h_init(&h, NULL);
	s0 = h_word(&h, SH2000_W_SNAP_SEQ_END);
	for (i = 1; i <= 50; i++) {
		h_cycles(&h, 1);
		assert_int_equal(h_word(&h, SH2000_W_SNAP_SEQ_BEGIN),
				 h_word(&h, SH2000_W_SNAP_SEQ_END));
		assert_int_equal(h_word(&h, SH2000_W_SNAP_SEQ_END),
				 (uint16_t)(s0 + i / 10));
	}
	assert_int_equal(h_set_i(&h, SH2000_AXIS_GLOBAL, SH2000_GP_STATUS_PERIOD, 1),
			 SH2000_RES_OK);
	s0 = h_word(&h, SH2000_W_SNAP_SEQ_END);
	h_cycles(&h, 7);
	assert_int_equal(h_word(&h, SH2000_W_SNAP_SEQ_END), (uint16_t)(s0 + 7));
	h_fini(&h);
}

static void body(void **state)
{
	struct harness h;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 }, cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES], t;
	unsigned int i, a;

	(void)state;
	h_init(&h, NULL);
	assert_int_equal(h_cmd(&h, SH2000_CMD_ENABLE, 0, 0, 0xf, NULL), SH2000_RES_OK);
	for (i = 1; i <= 30; i++) {
		p[0] = (int32_t)(i * 3000);
		p[3] = -(int32_t)(i * 1000);
		h_push(&h, p, (uint16_t)i, i == 30 ? SH2000_REC_F_END : 0);
	}
	while ((h.fw->dsp.cycle + 1) % 10)
		h_cycles(&h, 1);
	h_cycles(&h, 301);	/* lands on a publication */
	assert_int_equal(h.fw->dsp.cycle % 10, 0);
	h_snapshot(&h, cmd, act);
	t = h_word(&h, SH2000_W_SNAP_TIME_LO) |
	    ((uint32_t)h_word(&h, SH2000_W_SNAP_TIME_HI) << 16);
	assert_int_equal(t, (uint32_t)h.fw->dsp.cycle);
	for (a = 0; a < SH2000_AXES; a++) {
		assert_int_equal(cmd[a], (int32_t)nearbyint(h.fw->dsp.ax[a].cmd));
		assert_int_equal(act[a], h.fw->dsp.ax[a].counter);
		assert_int_equal((int16_t)h_word(&h, SH2000_W_SNAP_AXIS(a) + SH2000_SNAP_DAC),
				 h.fw->dsp.ax[a].dac);
	}
	assert_true(cmd[0] > 0 && cmd[3] < 0);
	h_fini(&h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(period),
		cmocka_unit_test(body),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
