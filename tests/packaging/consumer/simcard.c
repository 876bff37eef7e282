/* SPDX-License-Identifier: MIT */
/*
 * A program outside the project built against the installed libsh2000-sim
 * (pkg-config sh2000-sim or find_package(sh2000 COMPONENTS sim)): it opens
 * an in-process simulated card with its own plant configuration (X's
 * positive limit switch below where X powers up), lets 10 ms of card time
 * pass and checks that the card ran its servo cycles and shows X, and only
 * X, on its limit switch. It prints both libraries' versions, which must
 * agree (libsh2000-sim is pinned to its libsh2000).
 */
#include <sh2000/sh2000.h>
#include <sh2000/sim.h>

#include <stdio.h>
#include <string.h>


static int check_card(struct sh2000 *h)
{
	struct sh2000_status st;
	struct sh2000_probe pr;
	int r;

	r = sh2000_sleep_ns(h, 10000000u);
	if (r >= 0)
		r = sh2000_poll(h, &st);
	if (r >= 0)
		r = sh2000_sim_probe(h, &pr);
	if (r < 0) {
		fprintf(stderr, "simcard: %s\n", sh2000_strerror(r));
		return 1;
	}
	printf("simcard: after %llu servo cycles: X %s, Y %s on the + limit switch\n",
	       (unsigned long long)pr.servo_cycle,
	       st.axis[0].state & SH2000_AXIS_LIMIT_POS ? "is" : "is not",
	       st.axis[1].state & SH2000_AXIS_LIMIT_POS ? "is" : "is not");
	return pr.servo_cycle == 0 ||
	       !(st.axis[0].state & SH2000_AXIS_LIMIT_POS) ||
	       (st.axis[1].state & SH2000_AXIS_LIMIT_POS);
}

int main(void)
{
	struct sh2000_sim_config cfg;
	struct sh2000 *h;
	char msg[256];
	int bad;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].limit_pos_mm = cfg.axis[0].start_mm - 10.0;
	if (sh2000_sim_open(&h, &cfg, msg, sizeof(msg)) < 0) {
		fprintf(stderr, "simcard: %s\n", msg);
		return 1;
	}
	bad = check_card(h);
	bad |= strcmp(sh2000_sim_version(), sh2000_version()) != 0;
	printf("simcard: %s: libsh2000-sim %s, libsh2000 %s on %s\n",
	       bad ? "FAIL" : "ok", sh2000_sim_version(), sh2000_version(),
	       sh2000_device(h));
	sh2000_close(h);
	return bad;
}
