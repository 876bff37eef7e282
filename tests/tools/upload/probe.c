// SPDX-License-Identifier: MIT
/*
 * Prints a card's state for the black-box tests: "state=S fill=N
 * enabled=MASK cmd=x,y,z,a pos=x,y,z,a" (mm, 4 decimals). Only polls,
 * unless asked to set one axis parameter first:
 *   probe DEVICE [AXIS NAME VALUE]
 * or prints only the servo cycle of the card's snapshot (the card's own
 * time, which the tests wait on instead of the wall clock's):
 *   probe DEVICE cycle
 */
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include <sh2000/sh2000.h>

int main(int argc, char **argv)
{
	struct sh2000_status st;
	struct sh2000 *h;
	char msg[256];
	unsigned int a, en = 0;

	if ((argc != 2 && argc != 3 && argc != 5) ||
	    (argc == 3 && strcmp(argv[2], "cycle"))) {
		fprintf(stderr, "usage: probe DEVICE [AXIS NAME VALUE | cycle]\n");
		return 2;
	}
	if (sh2000_open(&h, argv[1], msg, sizeof(msg)) < 0) {
		fprintf(stderr, "%s\n", msg);
		return 1;
	}
	if (argc == 5 && sh2000_param_set(h, atoi(argv[2]),
					  (unsigned int)sh2000_param_id(argv[3]),
					  atof(argv[4])) < 0) {
		fprintf(stderr, "%s\n", sh2000_last_error(h));
		sh2000_close(h);
		return 1;
	}
	if (sh2000_poll(h, &st) < 0) {
		fprintf(stderr, "%s\n", sh2000_last_error(h));
		sh2000_close(h);
		return 1;
	}
	if (argc == 3) {
		printf("%llu\n", (unsigned long long)st.card_cycle);
		sh2000_close(h);
		return 0;
	}
	for (a = 0; a < SH2000_AXES; a++)
		if (st.axis[a].state & SH2000_AXIS_ENABLED)
			en |= 1u << a;
	printf("state=%u fill=%u enabled=%x cmd=%.4f,%.4f,%.4f,%.4f pos=%.4f,%.4f,%.4f,%.4f\n",
	       st.card_state, st.queue_fill, en, st.axis[0].cmd_mm,
	       st.axis[1].cmd_mm, st.axis[2].cmd_mm, st.axis[3].cmd_mm,
	       st.axis[0].pos_mm, st.axis[1].pos_mm, st.axis[2].pos_mm,
	       st.axis[3].pos_mm);
	sh2000_close(h);
	return 0;
}
