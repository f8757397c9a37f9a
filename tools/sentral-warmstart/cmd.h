/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the commands, written against the backend interface
 * and an environment (output streams and clocks) so tests can fake both.
 */
#ifndef SW_CMD_H
#define SW_CMD_H

#include "backend.h"
#include "cli.h"

struct sw_env {
	FILE *out;
	FILE *err;
	bool tty;		/* out is a terminal: draw a progress bar */
	bool kmsg;		/* run by udev: copy messages to /dev/kmsg */
	void *clk;
	uint64_t (*now_ms)(void *clk);		/* monotonic */
	void (*sleep_ms)(void *clk, unsigned int ms);
	/* as sleep_ms, cut short by SIGINT, SIGTERM or SIGHUP (watch) */
	void (*nap_ms)(void *clk, unsigned int ms);
	uint64_t (*wall_s)(void *clk);		/* seconds since the epoch */
};

/* How long a writer waits for another one to finish (see wsfile.h). */
#define SW_LOCK_WAIT_MS 30000

/* Real clocks; out/err/tty/kmsg are the caller's. */
void sw_env_init(struct sw_env *env, FILE *out, FILE *err);

/* An informational line on out (and in the kernel log when run by udev). */
void sw_note(struct sw_env *env, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* "sentral-warmstart: error: ..." on err (and in the kernel log). */
void sw_report(struct sw_env *env, const struct sw_err *e);

/* s as a JSON string, quoted and escaped. */
void sw_json_str(FILE *f, const char *s);

/* --file, or STATE_DIR/KEY.ws. */
void sw_file_path(const struct sw_opts *o, const struct sw_backend *b,
		  char *out, size_t len);

int sw_cmd_status(struct sw_backend *b, const struct sw_opts *o,
		  struct sw_env *env, struct sw_err *e);
int sw_cmd_save(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, struct sw_err *e);
int sw_cmd_restore(struct sw_backend *b, const struct sw_opts *o,
		   struct sw_env *env, struct sw_err *e);
/* Check o->file and print it: text, or with --json one object. */
int sw_cmd_show(const struct sw_opts *o, struct sw_env *env,
		struct sw_err *e);
int sw_cmd_calibrate(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, struct sw_err *e);
/*
 * The chip's key; with --udev the udev properties SENTRAL_WARMSTART_KEY and
 * SENTRAL_WARMSTART_UNIT (the key escaped as a unit instance name); with
 * --json one object: device, backend, key, unit (null when too long for a
 * unit name) and file (the saved file's path).
 */
int sw_cmd_key(struct sw_backend *b, const struct sw_opts *o,
	       struct sw_env *env, struct sw_err *e);
int sw_cmd_accel_cal(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, struct sw_err *e);
/*
 * Stay running: read the calibration state every o->poll_s and save by
 * the policy (improve_only, margin, at most one write per o->interval_s;
 * a save held back by it is made when allowed, if still wanted). Without
 * a score, the blob is read when the level rises to 4 (or is 4 at the
 * first look), not while it stays. Ends with SW_EXIT_OK on SIGINT, SIGTERM
 * or SIGHUP, with SW_EXIT_DEVICE when the device goes away.
 */
int sw_cmd_watch(struct sw_backend *b, const struct sw_opts *o,
		 struct sw_env *env, struct sw_err *e);

/*
 * Read the EEPROM image o->image, find the USFS utilities' block of
 * o->layout (board.h), check it as a saved file is checked, and save its
 * parameters for the chip present through the save's lock and atomic
 * write, by sw_policy_import(). A refused image is SW_EXIT_FILE, a missing
 * one SW_EXIT_NOFILE; nothing is written then.
 */
int sw_cmd_import_board(struct sw_backend *b, const struct sw_opts *o,
			struct sw_env *env, struct sw_err *e);

/*
 * A snapshot of the chip: the calibration state, the blob and the state
 * again, checked (sw_cal_state_check(), else SW_EXIT_IO); *cs is the worse
 * of the two states (see sw_save_now()). One blob read.
 */
int sw_read_snapshot(struct sw_backend *b, struct sw_cal_state *cs,
		     uint8_t *blob, struct sw_err *e);

/*
 * save: a snapshot (sw_read_snapshot()), saved by the policy; *saved (may
 * be NULL) says whether a file was written. The blob is judged by the
 * worse of the states before and after its read: stable means level 4 on
 * both, and a calibration that changed under the read is judged by the
 * worse. Writers of one file take turns (sw_file_lock_open()), waiting
 * SW_LOCK_WAIT_MS at most. A glitched read (EIO, a value out of range) is
 * an error and saves nothing.
 */
int sw_save_now(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, bool *saved, struct sw_err *e);

/*
 * Would the policy save a calibration in state cs? Reads the saved file,
 * the chip's identity, and the chip's accel offsets from blob, or when
 * blob is NULL from the driver's copy (no bus transaction with the
 * driver); without blob the stable rule cannot compare the magnetometer
 * coefficients and says no unless there is another reason.
 */
int sw_save_wanted(struct sw_backend *b, const struct sw_opts *o,
		   const struct sw_cal_state *cs, const uint8_t *blob,
		   bool *yes, char *why, size_t len, struct sw_err *e);

/*
 * Apply the save policy to a snapshot (calibration state + blob taken
 * together) and write it. Shared by save and calibrate. The policy saying
 * no returns SW_EXIT_OK with *saved false (saved may be NULL).
 */
int sw_save_snapshot(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, const struct sw_cal_state *cs,
		     const uint8_t *blob, bool *saved, struct sw_err *e);

#endif
