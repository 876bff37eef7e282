/* SPDX-License-Identifier: MIT */
/* Card methods defined outside card.c (card.c's method table lists them). */
#ifndef SH2000_PY_CARD_METHODS_H
#define SH2000_PY_CARD_METHODS_H

#include "binding.h"

PyObject *sh2k_card_enable(PyCard *c, PyObject *args);
PyObject *sh2k_card_disable(PyCard *c, PyObject *args);
PyObject *sh2k_card_stop(PyCard *c, PyObject *unused);
PyObject *sh2k_card_reset(PyCard *c, PyObject *unused);
PyObject *sh2k_card_estop(PyCard *c, PyObject *args);
PyObject *sh2k_card_home(PyCard *c, PyObject *args);
PyObject *sh2k_card_set_position(PyCard *c, PyObject *args);
PyObject *sh2k_card_push_mm(PyCard *c, PyObject *args);
PyObject *sh2k_card_push_counts(PyCard *c, PyObject *args);
PyObject *sh2k_card_wait_space(PyCard *c, PyObject *args);
PyObject *sh2k_card_wait_idle(PyCard *c, PyObject *args);
PyObject *sh2k_card_wait_rest(PyCard *c, PyObject *args);
PyObject *sh2k_card_queue_free(PyCard *c, PyObject *unused);
PyObject *sh2k_card_now_ns(PyCard *c, PyObject *unused);
PyObject *sh2k_card_sleep_ns(PyCard *c, PyObject *args);
PyObject *sh2k_card_gather_start(PyCard *c, PyObject *args);
PyObject *sh2k_card_gather_stop(PyCard *c, PyObject *unused);
PyObject *sh2k_card_gather_info(PyCard *c, PyObject *unused);
PyObject *sh2k_card_gather_wait(PyCard *c, PyObject *args);
PyObject *sh2k_card_gather_read(PyCard *c, PyObject *args);
PyObject *sh2k_card_comp_load(PyCard *c, PyObject *args);
PyObject *sh2k_card_comp_clear(PyCard *c, PyObject *unused);
PyObject *sh2k_card_comp_status(PyCard *c, PyObject *unused);

#endif /* SH2000_PY_CARD_METHODS_H */
