// SPDX-License-Identifier: MIT
/* docs/protocol.md and sh2000_protocol.h must agree: every parameter row
 * carries the header's id, name and default; every result code, reject
 * reason, state and fault bit is in the document with its value. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "sh2000/sh2000_protocol.h"

static char *doc;

static int load(void **state)
{
	FILE *f = fopen(SH2000_PROTOCOL_DOC, "rb");
	long n;

	(void)state;
	if (!f)
		return -1;
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	fseek(f, 0, SEEK_SET);
	doc = calloc(1, (size_t)n + 1);
	if (!doc || fread(doc, 1, (size_t)n, f) != (size_t)n) {
		fclose(f);
		return -1;
	}
	fclose(f);
	return 0;
}

static int unload(void **state)
{
	(void)state;
	free(doc);
	return 0;
}

static void has(const char *needle)
{
	if (!strstr(doc, needle))
		fail_msg("docs/protocol.md lacks \"%s\"", needle);
}

static void params(void **state)
{
	unsigned int id;
	char row[128];

	(void)state;
	for (id = 0; id < SH2000_GP_END; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (!p)
			continue;
		snprintf(row, sizeof(row), "| %u | `%s` | %s |", id, p->name,
			 p->type == SH2000_PT_F32 ? "F32" : "I32");
		has(row);
	}
}

static void values(void **state)
{
	static const struct { const char *name; unsigned int v; } rows[] = {
		{ "`NOP`", SH2000_CMD_NOP }, { "`ENABLE`", SH2000_CMD_ENABLE },
		{ "`DISABLE`", SH2000_CMD_DISABLE },
		{ "`SET_PARAM`", SH2000_CMD_SET_PARAM },
		{ "`GET_PARAM`", SH2000_CMD_GET_PARAM }, { "`HOME`", SH2000_CMD_HOME },
		{ "`STOP`", SH2000_CMD_STOP }, { "`RESET`", SH2000_CMD_RESET },
		{ "`SET_POSITION`", SH2000_CMD_SET_POSITION },
		{ "`GATHER_SET`", SH2000_CMD_GATHER_SET },
		{ "`GATHER_ARM`", SH2000_CMD_GATHER_ARM },
		{ "`GATHER_STOP`", SH2000_CMD_GATHER_STOP },
		{ "`GATHER_INFO`", SH2000_CMD_GATHER_INFO },
		{ "`GATHER_READ`", SH2000_CMD_GATHER_READ },
		{ "`COMP_BEGIN`", SH2000_CMD_COMP_BEGIN },
		{ "`COMP_PAGE`", SH2000_CMD_COMP_PAGE },
		{ "`COMP_COMMIT`", SH2000_CMD_COMP_COMMIT },
		{ "`COMP_CLEAR`", SH2000_CMD_COMP_CLEAR },
		{ "`INDEX_ARM`", SH2000_CMD_INDEX_ARM },
		{ "`INDEX_DISARM`", SH2000_CMD_INDEX_DISARM },
		{ "`NOW`", SH2000_GATHER_NOW },
		{ "`ON_MOTION`", SH2000_GATHER_ON_MOTION },
		{ "`ON_FAULT`", SH2000_GATHER_ON_FAULT },
		{ "`REJECT_DROPPED`", SH2000_REJECT_DROPPED },
		{ "`REJECT_CHECKSUM`", SH2000_REJECT_CHECKSUM },
		{ "`REJECT_RESERVED`", SH2000_REJECT_RESERVED },
		{ "`REJECT_DISABLED`", SH2000_REJECT_DISABLED },
		{ "`REJECT_SOFT_LIMIT`", SH2000_REJECT_SOFT_LIMIT },
		{ "`REJECT_VELOCITY`", SH2000_REJECT_VELOCITY },
		{ "`REJECT_STATE`", SH2000_REJECT_STATE },
		{ "BOOT", SH2000_STATE_BOOT }, { "IDLE", SH2000_STATE_IDLE },
		{ "RUNNING", SH2000_STATE_RUNNING }, { "STOPPING", SH2000_STATE_STOPPING },
		{ "HOMING", SH2000_STATE_HOMING }, { "FAULT", SH2000_STATE_FAULT },
		{ "ESTOP", SH2000_STATE_ESTOP },
	};
	static const struct { const char *name; unsigned int bit; } bits[] = {
		{ "`UNDERRUN`", SH2000_FAULT_UNDERRUN },
		{ "`HOST_TIMEOUT`", SH2000_FAULT_HOST_TIMEOUT },
		{ "`ESTOP`", SH2000_FAULT_ESTOP }, { "`REJECTED`", SH2000_FAULT_REJECTED },
		{ "`PROTOCOL`", SH2000_FAULT_PROTOCOL }, { "`AXIS`", SH2000_FAULT_AXIS },
		{ "`FERR`", SH2000_AXIS_FAULT_FERR },
		{ "`SOFT_LIMIT`", SH2000_AXIS_FAULT_SOFT_LIMIT },
		{ "`HARD_LIMIT`", SH2000_AXIS_FAULT_HARD_LIMIT },
		{ "`DAC_SAT`", SH2000_AXIS_FAULT_DAC_SAT },
		{ "`COUNTER`", SH2000_AXIS_FAULT_COUNTER },
		{ "`HOME`", SH2000_AXIS_FAULT_HOME },
		{ "`SKEW`", SH2000_AXIS_FAULT_SKEW },
	};
	char row[128];
	unsigned int i;

	(void)state;
	for (i = 0; i < sizeof(rows) / sizeof(rows[0]); i++) {
		snprintf(row, sizeof(row), "| %s | %u |", rows[i].name, rows[i].v);
		has(row);
	}
	for (i = 0; i < sizeof(bits) / sizeof(bits[0]); i++) {
		snprintf(row, sizeof(row), "| 0x%02x | %s |", bits[i].bit, bits[i].name);
		has(row);
	}
	snprintf(row, sizeof(row), "`OK` %u, `BAD_OP` %u, `BAD_AXIS` %u, `BAD_PARAM` %u, "
		 "`BAD_VALUE` %u,\n`BUSY` %u, `FAULTED` %u, `CHECKSUM` %u, `DISABLED` %u",
		 SH2000_RES_OK, SH2000_RES_BAD_OP, SH2000_RES_BAD_AXIS,
		 SH2000_RES_BAD_PARAM, SH2000_RES_BAD_VALUE, SH2000_RES_BUSY,
		 SH2000_RES_FAULTED, SH2000_RES_CHECKSUM, SH2000_RES_DISABLED);
	has(row);
}

/* Protocol 1.2: every gather signal with its bit, name and type; the
 * fields; the window's words. */
static void gather(void **state)
{
	static const struct { const char *name; unsigned int w; } win[] = {
		{ "`GW_CHECK`", SH2000_GW_CHECK }, { "`GW_SEQ`", SH2000_GW_SEQ },
		{ "`GW_KIND`", SH2000_GW_KIND }, { "`GW_RECORD`", SH2000_GW_RECORD },
		{ "`GW_COUNT`", SH2000_GW_COUNT }, { "`GW_STATE`", SH2000_GW_STATE },
	};
	static const char *const fields[SH2000_GATHER_FIELDS] = {
		"SIGNALS", "PERIOD", "SAMPLES", "TRIGGER", "PRETRIGGER",
	};
	char row[128];
	unsigned int i;

	(void)state;
	for (i = 0; i < SH2000_GATHER_SIGNALS; i++) {
		const struct sh2000_gather_signal_info *g = sh2000_gather_signal_lookup(i);

		snprintf(row, sizeof(row), "| %u | `%s` | %s | %s |", i, g->name,
			 g->type == SH2000_PT_F32 ? "F32" : "I32", g->unit);
		has(row);
	}
	for (i = 0; i < SH2000_GATHER_FIELDS; i++) {
		snprintf(row, sizeof(row), "| %u | `%s` |", i, fields[i]);
		has(row);
	}
	for (i = 0; i < sizeof(win) / sizeof(win[0]); i++) {
		snprintf(row, sizeof(row), "| %u | %s |",
			 SH2000_W_GATHER_BASE + win[i].w, win[i].name);
		has(row);
	}
	snprintf(row, sizeof(row), "| %u..%u | gather window |", SH2000_W_GATHER_BASE,
		 SH2000_W_GATHER_BASE + SH2000_GATHER_WINDOW_WORDS - 1);
	has(row);
	snprintf(row, sizeof(row), "up to %u values", SH2000_GATHER_CHUNK_VALUES);
	has(row);
	snprintf(row, sizeof(row), "a %u-word payload", SH2000_GATHER_INFO_WORDS);
	has(row);
}

static void layout(void **state)
{
	static const struct { const char *name; unsigned int w; } rows[] = {
		{ "`ESTOP_REQ`", SH2000_W_ESTOP_REQ }, { "`MAGIC`", SH2000_W_MAGIC },
		{ "`VERSION`", SH2000_W_VERSION }, { "`HEARTBEAT`", SH2000_W_HEARTBEAT },
		{ "`ESTOP_ACK`", SH2000_W_ESTOP_ACK }, { "`STATE`", SH2000_W_STATE },
		{ "`FAULTS`", SH2000_W_FAULTS }, { "`TAIL`", SH2000_W_TAIL },
		{ "`CMD_ACK`", SH2000_W_CMD_ACK }, { "`CMD_RESULT`", SH2000_W_CMD_RESULT },
		{ "`REJECT_SEQ`", SH2000_W_REJECT_SEQ },
		{ "`REJECT_REASON`", SH2000_W_REJECT_REASON },
		{ "`REJECT_COUNT`", SH2000_W_REJECT_COUNT },
		{ "`SNAP_SEQ_END`", SH2000_W_SNAP_SEQ_END },
		{ "`SNAP_SEQ_BEGIN`", SH2000_W_SNAP_SEQ_BEGIN },
		{ "`HOST_HEARTBEAT`", SH2000_W_HOST_HEARTBEAT }, { "`HEAD`", SH2000_W_HEAD },
		{ "`CMD_OP`", SH2000_W_CMD_OP }, { "`CMD_AXIS`", SH2000_W_CMD_AXIS },
		{ "`CMD_PARAM`", SH2000_W_CMD_PARAM }, { "`CMD_CHECK`", SH2000_W_CMD_CHECK },
		{ "`CMD_SEQ`", SH2000_W_CMD_SEQ },
	};
	char row[128];
	unsigned int i;

	(void)state;
	for (i = 0; i < sizeof(rows) / sizeof(rows[0]); i++) {
		snprintf(row, sizeof(row), "| %u | %s |", rows[i].w, rows[i].name);
		has(row);
	}
	snprintf(row, sizeof(row), "| %u..%u | ring |", SH2000_W_RING_BASE, SH2000_W_RING_END - 1);
	has(row);
}

/* The first-fault record (1.4) took reserved words: after the ring,
 * before the gather window, and the table says where. */
static void first_fault(void **state)
{
	static const struct { const char *name; unsigned int off; } rows[] = {
		{ "`FIRST_FAULT`+`FF_BIT`", SH2000_FF_BIT },
		{ "`FIRST_FAULT`+`FF_AXIS`", SH2000_FF_AXIS },
		{ "`FIRST_FAULT`+`FF_CHECK`", SH2000_FF_CHECK },
	};
	unsigned int end = SH2000_W_FIRST_FAULT + SH2000_FIRST_FAULT_WORDS, i;
	char row[128];

	(void)state;
	assert_true(SH2000_W_FIRST_FAULT >= SH2000_W_RING_END);
	assert_true(end <= SH2000_W_GATHER_BASE);
	for (i = 0; i < sizeof(rows) / sizeof(rows[0]); i++) {
		snprintf(row, sizeof(row), "| %u | %s |",
			 SH2000_W_FIRST_FAULT + rows[i].off, rows[i].name);
		has(row);
	}
	snprintf(row, sizeof(row), "| %u, %u | `FIRST_FAULT`+`FF_CYCLE_LO/HI` |",
		 SH2000_W_FIRST_FAULT + SH2000_FF_CYCLE_LO,
		 SH2000_W_FIRST_FAULT + SH2000_FF_CYCLE_HI);
	has(row);
	snprintf(row, sizeof(row), "| %u..%u | reserved |", end, SH2000_W_INDEX(0) - 1);
	has(row);
	/* the index blocks (1.6) took reserved words after it, up to 1.5's
	 * compensation status, which ends the reserved words: no overlap */
	assert_true(SH2000_W_INDEX(0) >= end);
	assert_int_equal(SH2000_W_INDEX(SH2000_AXES), SH2000_W_COMP_STATUS);
	snprintf(row, sizeof(row), "| %u + 7a | `INDEX(a)`+`IX_STATE` |", SH2000_W_INDEX(0));
	has(row);
	snprintf(row, sizeof(row), "| %u + 7a | `INDEX(a)`+`IX_CHECK` |",
		 SH2000_W_INDEX(0) + SH2000_IX_CHECK);
	has(row);
	assert_int_equal(SH2000_W_COMP_STATUS + SH2000_COMP_STATUS_WORDS, SH2000_W_GATHER_BASE);
	snprintf(row, sizeof(row), "| %u..%u | `COMP_STATUS` |", SH2000_W_COMP_STATUS,
		 SH2000_W_COMP_STATUS + SH2000_COMP_STATUS_WORDS - 1);
	has(row);
	snprintf(row, sizeof(row), "Version: **%u.%u**", SH2000_PROTO_MAJOR,
		 SH2000_PROTO_MINOR);
	has(row);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(params),
		cmocka_unit_test(values),
		cmocka_unit_test(layout),
		cmocka_unit_test(first_fault),
		cmocka_unit_test(gather),
	};

	return cmocka_run_group_tests(tests, load, unload);
}
