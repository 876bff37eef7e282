/* SPDX-License-Identifier: MIT */
/*
 * A program outside the project, built against the installed libsh2000
 * alone (pkg-config sh2000, find_package(sh2000)): it opens the card named
 * on the command line and prints its state and the versions. On `sim`
 * libsh2000 loads libsh2000-sim.so.0 itself: the program neither links
 * nor includes anything of it.
 */
#include <sh2000/sh2000.h>
#include <sh2000/sh2000_protocol.h>
#include <sh2000/uapi/sh2000.h>

#include <stdio.h>

int main(int argc, char **argv)
{
	const char *dev = argc > 1 ? argv[1] : "sim";
	struct sh2000_status st;
	struct sh2000 *h;
	char msg[512];	/* as the tools: a message names a path and a remedy */
	int r;

	r = sh2000_open(&h, dev, msg, sizeof(msg));
	if (r < 0) {
		fprintf(stderr, "consumer: %s\n", msg);
		return 1;
	}
	r = sh2000_poll(h, &st);
	if (r < 0) {
		fprintf(stderr, "consumer: poll: %s\n", sh2000_strerror(r));
		sh2000_close(h);
		return 1;
	}
	printf("consumer: libsh2000 %s (libsh2000.so.%u), %s: card state %u, "
	       "protocol %u.%u (card 0x%04x), driver ABI %d\n",
	       sh2000_version(), sh2000_soversion(), sh2000_device(h),
	       st.card_state, SH2000_PROTO_MAJOR, SH2000_PROTO_MINOR,
	       sh2000_card_version(h), SH2000_ABI_VERSION);
	sh2000_close(h);
	return 0;
}
