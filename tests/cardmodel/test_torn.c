// SPDX-License-Identifier: MIT
/* The firmware in one thread on a shared RAM, a reader in another using
 * the torn-read rule: the snapshot time never goes backwards and never
 * mixes halves, although the reader sees many publications mid-way. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "card_internal.h"

#define CYCLES 300000u

static uint16_t ram[1024];
static int done;

static void *card(void *arg)
{
	struct sh2000_fw *fw = arg;
	unsigned int i;

	for (i = 0; i < CYCLES; i++)
		sh2000_fw_cycle(fw);
	__atomic_store_n(&done, 1, __ATOMIC_RELEASE);
	return NULL;
}

static void torn(void **state)
{
	struct sh2000_fw *fw;
	pthread_t th;
	uint32_t last = 0;
	unsigned long polls = 0, retries = 0;

	(void)state;
	assert_int_equal(sh2000_fw_create(&fw, ram, NULL), 0);
	/* publish every cycle so that the reader often overlaps */
	fw->dsp.status_period = 1;
	assert_int_equal(pthread_create(&th, NULL, card, fw), 0);
	while (!__atomic_load_n(&done, __ATOMIC_ACQUIRE)) {
		uint16_t end, begin, lo, hi;
		unsigned int w;
		uint32_t t;

		end = sh2000_dpram_read(ram, SH2000_W_SNAP_SEQ_END);
		for (w = SH2000_W_SNAP_AXIS(0); w < SH2000_W_SNAP_TIME_LO; w++)
			(void)sh2000_dpram_read(ram, w);
		lo = sh2000_dpram_read(ram, SH2000_W_SNAP_TIME_LO);
		hi = sh2000_dpram_read(ram, SH2000_W_SNAP_TIME_HI);
		begin = sh2000_dpram_read(ram, SH2000_W_SNAP_SEQ_BEGIN);
		polls++;
		if (begin != end) {
			retries++;
			continue;
		}
		t = lo | ((uint32_t)hi << 16);
		assert_true(t >= last);
		assert_true(t <= CYCLES);
		last = t;
	}
	pthread_join(th, NULL);
	printf("# %lu polls, %lu detected overlaps retried, last time %u\n", polls, retries, last);
	sh2000_fw_destroy(fw);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(torn),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
