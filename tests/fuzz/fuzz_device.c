// SPDX-License-Identifier: MIT
/*
 * sh2000_open() with arbitrary device strings, in a fake environment: the
 * library's open(), shm_open() and ioperm() are wrapped at link time
 * (-Wl,--wrap) while the call runs, so no real device, port, shared
 * memory object or lock file is ever touched. A path "opens" as a file
 * that is no sh2000 device or fails with ENOENT, EACCES or EPERM; a
 * shared-memory name is never served; ports are refused. `sim` opens the
 * in-process card for real.
 *
 * The first byte is the size of the message buffer (0: none), the rest
 * the device string. Promises checked: 0 only with a handle, else a
 * negative code, no handle, and a message in the buffer (ASan sees any
 * write past its size).
 */
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/types.h>

#include <sh2000/sh2000.h>

#include "fuzz.h"

int __real_open(const char *path, int flags, ...);
int __wrap_open(const char *path, int flags, ...);
int __wrap_shm_open(const char *name, int oflag, mode_t mode);
int __wrap_ioperm(unsigned long from, unsigned long num, int on);

static int faking;	/* inside sh2000_open() */

static unsigned int hash(const char *s)
{
	unsigned int h = 2166136261u;

	while (*s)
		h = (h ^ (unsigned char)*s++) * 16777619u;
	return h;
}

int __wrap_open(const char *path, int flags, ...)
{
	static const int fail[] = { ENOENT, EACCES, EPERM };
	mode_t mode = 0;
	unsigned int h;

	if (flags & (O_CREAT | O_TMPFILE)) {
		va_list ap;

		va_start(ap, flags);
		mode = va_arg(ap, mode_t);
		va_end(ap);
	}
	if (!faking)
		return __real_open(path, flags, mode);
	h = hash(path) % 4;
	if (h < 3) {
		errno = fail[h];
		return -1;
	}
	return memfd_create("fuzz-not-a-card", MFD_CLOEXEC);
}

int __wrap_shm_open(const char *name, int oflag, mode_t mode)
{
	(void)oflag;
	(void)mode;
	errno = hash(name) % 2 ? ENOENT : EACCES;
	return -1;
}

int __wrap_ioperm(unsigned long from, unsigned long num, int on)
{
	(void)from;
	(void)num;
	(void)on;
	errno = EPERM;
	return -1;
}

int LLVMFuzzerInitialize(int *argc, char ***argv);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	unsetenv("SH2000_DEVICE");
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct sh2000 *h = (struct sh2000 *)&h;	/* must become NULL */
	size_t msglen;
	char *dev, *msg;
	int r;

	if (size < 1)
		return 0;
	msglen = data[0];
	dev = malloc(size);
	msg = msglen ? malloc(msglen) : NULL;
	if (!dev || (msglen && !msg))
		fz_fail("out of memory");
	memcpy(dev, data + 1, size - 1);
	dev[size - 1] = '\0';
	if (msg)
		memset(msg, 'x', msglen);
	faking = 1;
	r = sh2000_open(&h, dev, msg, msglen);
	faking = 0;
	if (r == 0 && !h)
		fz_fail("'%s': opened without a handle", dev);
	if (r != 0 && (r > 0 || h))
		fz_fail("'%s': returned %d with a handle %p", dev, r,
			(void *)h);
	if (r < 0 && msg && (!memchr(msg, '\0', msglen) ||
			     (msglen > 1 && !msg[0])))
		fz_fail("'%s': %d without a message", dev, r);
	sh2000_close(r == 0 ? h : NULL);
	free(msg);
	free(dev);
	return 0;
}
