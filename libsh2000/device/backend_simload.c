/* SPDX-License-Identifier: MIT */
/*
 * `sim`: the simulated card lives in libsh2000-sim, not in this library
 * (its symbols are no part of libsh2000's ABI). Opening `sim` loads
 * libsh2000-sim.so.0 beside this library (or SH2000_SIM_LIBRARY), asks its
 * provider for a card behind four registers and opens that like any
 * struct sh2000_ports. A program that links libsh2000-sim itself (the
 * static tools of the VM suite's initramfs, the tests) has the provider
 * already and nothing is loaded.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef SH2000_NO_DLOPEN
#include <dlfcn.h>
#endif

#include "sh2000_internal.h"
#include "sh2000_simprovider.h"

/* A program that links libsh2000-sim (statically, or a build without
 * dlopen) defines the provider itself: weak, so that libsh2000 links
 * without it. */
extern const struct sh2000_sim_provider sh2000_sim_provider_v1
	__attribute__((weak));

#ifdef SH2000_NO_DLOPEN

static const struct sh2000_sim_provider *load_provider(char *msg, size_t len)
{
	sh2000_msg(msg, len, -ENOENT,
		   "sim: this program was built without the simulated card (link libsh2000-sim)");
	return NULL;
}

#else

/* How a user gets the simulator: built from source beside libsh2000, or
 * its package. */
#define SH2000_SIM_HOWTO \
	"from source: cmake --build BUILD_DIR --target sh2000_sim; " \
	"from packages: apt install libsh2000-sim"

/* The directory libsh2000.so itself was loaded from: the simulator is
 * installed beside it, and a sanitizer's dlopen does not honour our
 * RUNPATH. */
static void *open_beside_us(void)
{
	char path[4096];
	const char *slash;
	Dl_info info;

	if (!dladdr((void *)&sh2000_ports_attach, &info) || !info.dli_fname)
		return NULL;
	slash = strrchr(info.dli_fname, '/');
	if (!slash)
		return NULL;
	if (snprintf(path, sizeof(path), "%.*s/%s",
		     (int)(slash - info.dli_fname), info.dli_fname,
		     SH2000_SIM_SONAME) >= (int)sizeof(path))
		return NULL;
	return dlopen(path, RTLD_NOW | RTLD_LOCAL);
}

static const struct sh2000_sim_provider *load_provider(char *msg, size_t len)
{
	static pthread_mutex_t once = PTHREAD_MUTEX_INITIALIZER;
	static const struct sh2000_sim_provider *prov;
	const char *lib = getenv("SH2000_SIM_LIBRARY");
	int own = !(lib && *lib);
	const char *what = own ? SH2000_SIM_SONAME : lib;
	void *dl;

	pthread_mutex_lock(&once);
	if (prov)
		goto out;
	dl = dlopen(what, RTLD_NOW | RTLD_LOCAL);
	if (!dl && own)
		dl = open_beside_us();
	if (!dl) {
		sh2000_msg(msg, len, -ENOENT,
			   "sim: cannot load the simulated card %s: %s (%s)",
			   what, dlerror(), SH2000_SIM_HOWTO);
		goto out;
	}
	/* kept loaded for the life of the process: handles point into it */
	prov = dlsym(dl, SH2000_SIM_PROVIDER_SYMBOL);
	if (!prov)
		sh2000_msg(msg, len, -ENOENT, "sim: %s has no %s", what,
			   SH2000_SIM_PROVIDER_SYMBOL);
out:
	pthread_mutex_unlock(&once);
	return prov;
}

#endif

static const struct sh2000_sim_provider *find_provider(char *msg, size_t len)
{
	if (&sh2000_sim_provider_v1)
		return &sh2000_sim_provider_v1;
	return load_provider(msg, len);
}

int sh2000_simload_open(struct sh2000 *h, char *msg, size_t len)
{
	const struct sh2000_sim_provider *prov = find_provider(msg, len);
	struct sh2000_ports p;
	int r;

	if (!prov)
		return -ENOENT;
	if (prov->abi != SH2000_SIM_PROVIDER_ABI)
		return sh2000_msg(msg, len, -SH2000_EVERSION,
				  "sim: libsh2000-sim provider ABI %u, this libsh2000 expects %u",
				  prov->abi, SH2000_SIM_PROVIDER_ABI);
	r = prov->open_ports(&p, msg, len);
	if (r < 0)
		return r;
	return sh2000_ports_attach(h, &p, msg, len);
}
