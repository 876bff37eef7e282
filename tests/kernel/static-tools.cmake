# SPDX-License-Identifier: GPL-2.0 OR MIT
# Included after project() (CMAKE_PROJECT_INCLUDE) by tests/kernel/run when
# it builds sh2000-sim, sh2000-upload and sh2000ctl with -static for the VM's
# busybox initramfs: pkg_check_modules resolves json-c to a full library path,
# so prefer the archive (Debian's libjson-c-dev ships libjson-c.a) wherever
# one exists. Libraries only the tests use (cmocka) may stay shared: the
# tests are not built.
set(CMAKE_FIND_LIBRARY_SUFFIXES .a .so)
