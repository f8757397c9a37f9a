/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the saved-file format ("SNTRLWS1", version 2; version
 * 1 files are still read).
 *
 * All fields little-endian; the byte layout is documented in
 * sentral-warmstart.8 (FILE FORMAT) and must match it:
 *
 *   off size field
 *     0    8 magic "SNTRLWS1"
 *     8    2 format version (2; 1 is read too)
 *    10    1 ProductID (reg 0x90)
 *    11    1 RevisionID (reg 0x91)
 *    12    2 ROM version (regs 0x70-0x71)
 *    14    2 RAM version (regs 0x72-0x73)
 *    16    1 version 2: calibration level at save time (0..4);
 *            version 1: the application note's status (0..3, 3 complete)
 *    17    1 version 2: judgement (0 none, 1 score, 2 stable);
 *            version 1: reserved, 0 (judged by the score)
 *    18    2 raw calibration score (0x4D | 0x4E << 8) when judged by the
 *            score, else 0
 *    20    8 save time, seconds since the Unix epoch
 *    28    2 payload size (140)
 *    30    2 reserved, 0
 *    32  140 payload: warm-start parameters 1..35, float32 each
 *   172    4 CRC-32 (zlib/IEEE 802.3) of bytes 0..171
 *   176      end of file
 */
#ifndef SW_WSFILE_H
#define SW_WSFILE_H

#include "sw.h"

#define SW_FILE_MAGIC "SNTRLWS1"
/* What the tool writes; version 1 (before the level) is still read. */
#define SW_FILE_VERSION 2
#define SW_FILE_VERSION_1 1
#define SW_FILE_HDR_SIZE 32
#define SW_FILE_SIZE (SW_FILE_HDR_SIZE + SW_BLOB_SIZE + 4)
/* Anything larger is not one of ours; do not read it into memory. */
#define SW_FILE_MAX_READ 4096

/* By what rule the calibration saved was judged good enough. */
enum sw_judgement {
	/* import-board: the board's EEPROM records no state at all */
	SW_JUDGED_NONE = 0,
	/* the application note's score (and status 3 or level 4) */
	SW_JUDGED_SCORE = 1,
	/* level 4 alone: the firmware reports no score */
	SW_JUDGED_STABLE = 2,
};

/* "none", "score", "stable"; "?" for anything else. */
const char *sw_judgement_name(enum sw_judgement j);

struct sw_file {
	struct sw_chip_info chip;
	/* SW_FILE_VERSION or SW_FILE_VERSION_1: what sw_file_encode() writes */
	int version;
	/*
	 * Byte 16 as the version defines it: the level (0..4) at save time,
	 * or in a version 1 file the status (0..3); see sw_file_level().
	 */
	int state;
	enum sw_judgement judgement;	/* version 1: SW_JUDGED_SCORE */
	uint16_t score_raw;		/* SW_JUDGED_SCORE only, else 0 */
	uint64_t saved_at;
	uint8_t payload[SW_BLOB_SIZE];
};

/*
 * The level a file was saved at: a version 1 file's status 3 (complete)
 * counts as 4 (stable), its 0..2 as 2 (calibrating).
 */
int sw_file_level(const struct sw_file *f);

/*
 * One phrase for messages: "level 4 (stable), score 2.499%",
 * "level 4 (stable), judged by the level", "imported from the board's
 * EEPROM, not judged" or "format 1: status 3, score 2.499%".
 */
void sw_file_describe(const struct sw_file *f, char *buf, size_t len);

/* The checks, each with a stable name used in messages and tests. */
enum sw_file_check {
	SW_CHECK_OK = 0,
	SW_CHECK_TRUNCATED,
	SW_CHECK_MAGIC,
	SW_CHECK_VERSION,
	SW_CHECK_PAYLOAD_SIZE,
	SW_CHECK_TRAILING,
	SW_CHECK_CRC,
	SW_CHECK_FIELD,
	SW_CHECK_NONFINITE,
	SW_CHECK_PRODUCT,
	SW_CHECK_ROM,
	SW_CHECK_RAM,
};

const char *sw_check_name(enum sw_file_check c);

/* Encode into buf (at least SW_FILE_SIZE bytes); returns SW_FILE_SIZE. */
size_t sw_file_encode(const struct sw_file *f, uint8_t *buf);

/*
 * Decode and validate the file's own consistency (no chip involved).
 * On failure returns the failed check and describes it in detail
 * (detail may be NULL).
 */
enum sw_file_check sw_file_decode(const uint8_t *buf, size_t len,
				  struct sw_file *f, char *detail,
				  size_t detail_len);

/* Index of the first non-finite parameter (1-based), 0 when all finite. */
int sw_blob_nonfinite(const uint8_t *blob);

/*
 * Compare a decoded file with the chip: ProductID, ROM and RAM version.
 * RevisionID is reported by `show` but not enforced.
 */
enum sw_file_check sw_file_match_chip(const struct sw_file *f,
				      const struct sw_chip_info *chip,
				      char *detail, size_t detail_len);

/* Name of warm-start parameter n (1..35), from the seed's table. */
const char *sw_param_name(int n);

/*
 * How far a file to be read is trusted. The state file decides what is
 * written into the chip at every boot, as root, and its CRC is no
 * authentication: whoever may change the file or its directory may
 * choose the calibration.
 */
enum sw_read_mode {
	/* show FILE: only printed; following a symlink the user named is harmless. */
	SW_READ_ANY,
	/*
	 * --file for restore, save and status: the last component must not
	 * be a symlink, the file must be owned by the effective user and not
	 * writable by group or others.
	 */
	SW_READ_OWNED,
	/*
	 * STATE_DIR/KEY.ws: as SW_READ_OWNED, and the directory must not be a
	 * symlink, must be owned by the effective user and not be writable
	 * by group or others; the file is opened relative to it.
	 */
	SW_READ_STATE,
};

/*
 * Read a whole file of at most SW_FILE_MAX_READ bytes. Neither the file
 * nor, except with SW_READ_ANY, its directory may be a symbolic link.
 * Returns SW_EXIT_OK or, with e->msg set: SW_EXIT_NOFILE (the file is
 * missing), SW_EXIT_STATEDIR (SW_READ_STATE: the directory is missing),
 * SW_EXIT_PERM (a symlink, or an owner or mode sw_read_mode refuses),
 * SW_EXIT_FILE (not a regular file) or SW_EXIT_IO. errno_out, when not
 * NULL, receives the errno of a failed open (EACCES, ENOENT, ELOOP...).
 */
int sw_file_read(const char *path, enum sw_read_mode mode, uint8_t *buf,
		 size_t *len, int *errno_out, struct sw_err *e);
/*
 * As sw_file_read(), for a file of at most max bytes (buf holds max + 1:
 * a longer file reads as max + 1 bytes). import-board reads an EEPROM
 * image with it.
 */
int sw_file_read_max(const char *path, enum sw_read_mode mode, uint8_t *buf,
		     size_t max, size_t *len, int *errno_out, struct sw_err *e);

/*
 * Atomically replace path with buf: temp file ".BASE.XXXXXXXX.tmp" in the
 * same directory (mode 0600, O_EXCL|O_NOFOLLOW, flock'ed until renamed),
 * write, fsync, rename, fsync the directory. Temp files of a killed save
 * (same pattern, unlocked, older than 2 s) are removed first. The
 * directory is created 0700 when missing (its parent must exist) and must
 * not be a symlink; an existing target that is a symlink or not a regular
 * file is refused. With state_dir (the directory is the state directory,
 * not --file's), it must also be owned by the effective user, and one the
 * tool did not create just now must not be open to group or others: it is
 * refused, never chmod'ed. No partial file is ever visible at path; the
 * temp file is removed on every error.
 */
int sw_file_write_atomic(const char *path, const uint8_t *buf, size_t len,
			 bool state_dir, struct sw_err *e);

/*
 * Remove what saves of path killed before their rename left behind, as
 * sw_file_write_atomic() does before it writes: for a file that is not
 * written every time. Best effort: errors are ignored.
 */
void sw_file_remove_stale_temps(const char *path);

/*
 * Writers of one file (save, watch, calibrate, accel-cal, restore setting
 * a refused file aside) take an flock(2) on its lock file ".BASE.lock" in
 * the same directory, so that the policy's look at the old file and the
 * rename that replaces it are one step. Readers need none: the rename is
 * atomic. sw_file_lock_open() creates the directory as
 * sw_file_write_atomic() does and the lock file with mode 0600, never
 * through a symlink, and refuses one that is not a regular file of the
 * effective user's (SW_EXIT_PERM). Returns the descriptor or an exit code
 * negated. The lock goes with the descriptor (close it to release).
 */
int sw_file_lock_open(const char *path, bool state_dir, struct sw_err *e);
/* Take the lock without waiting: false while another writer holds it. */
bool sw_file_lock_try(int fd);
/* The lock file's path, for messages. */
void sw_file_lock_name(const char *path, char *out, size_t len);

/*
 * Rename a state file within its (checked) state directory: to set a
 * refused file aside, or to move a file saved under an old key to the new
 * one. Without replace, an existing target is never overwritten (EEXIST).
 */
int sw_file_rename(const char *from, const char *to, bool replace,
		   struct sw_err *e);

#endif
