// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: status, save, restore and show.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "board.h"
#include "caldata.h"
#include "cmd.h"
#include "level.h"
#include "policy.h"
#include "wsfile.h"

/* How long restore waits for the level of a stable file (3 or 4). */
#define RESTORE_SETTLE_MS 2000
#define RESTORE_POLL_MS 20

static uint64_t real_now_ms(void *clk)
{
	struct timespec ts;

	(void)clk;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

static void real_sleep_ms(void *clk, unsigned int ms)
{
	struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };

	(void)clk;
	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

/*
 * The three signals are blocked but while asleep in ppoll(), so that one
 * that comes just before the sleep still ends it.
 */
static void real_nap_ms(void *clk, unsigned int ms)
{
	struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };
	sigset_t block, old;

	(void)clk;
	sigemptyset(&block);
	sigaddset(&block, SIGINT);
	sigaddset(&block, SIGTERM);
	sigaddset(&block, SIGHUP);
	sigprocmask(SIG_BLOCK, &block, &old);
	if (!sw_signal_pending())
		ppoll(NULL, 0, &ts, &old);
	sigprocmask(SIG_SETMASK, &old, NULL);
}

static uint64_t real_wall_s(void *clk)
{
	(void)clk;
	return (uint64_t)time(NULL);
}

void sw_env_init(struct sw_env *env, FILE *out, FILE *err)
{
	memset(env, 0, sizeof(*env));
	env->out = out;
	env->err = err;
	env->now_ms = real_now_ms;
	env->sleep_ms = real_sleep_ms;
	env->nap_ms = real_nap_ms;
	env->wall_s = real_wall_s;
}

/*
 * udev logs a RUN program's output only at debug level: put what matters
 * into the kernel log, where a boot's story is read.
 */
static void to_kmsg(int level, const char *msg)
{
	char line[700];
	int fd, n;

	fd = open("/dev/kmsg", O_WRONLY | O_CLOEXEC | O_NOCTTY);
	if (fd < 0)
		return;
	n = snprintf(line, sizeof(line), "<%d>sentral-warmstart[%d]: %s\n",
		     level, (int)getpid(), msg);
	if (n > 0 && write(fd, line, (size_t)n) < 0)
		n = 0;	/* the log is best effort */
	close(fd);
}

void sw_note(struct sw_env *env, const char *fmt, ...)
{
	char msg[600];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	fprintf(env->out, "%s\n", msg);
	fflush(env->out);
	if (env->kmsg)
		to_kmsg(5, msg);
}

void sw_report(struct sw_env *env, const struct sw_err *e)
{
	fprintf(env->err, "sentral-warmstart: error: %s\n", e->msg);
	fflush(env->err);
	if (env->kmsg) {
		char msg[560];

		snprintf(msg, sizeof(msg), "error: %s", e->msg);
		to_kmsg(3, msg);
	}
}

void sw_file_path(const struct sw_opts *o, const struct sw_backend *b,
		  char *out, size_t len)
{
	if (o->file)
		snprintf(out, len, "%s", o->file);
	else
		snprintf(out, len, "%s/%s.ws", o->state_dir, b->key);
}

static void fmt_time(uint64_t t, char *buf, size_t len)
{
	time_t tt = (time_t)t;
	struct tm tm;

	/* Beyond INT64_MAX the cast turns a file's time into one before 1970. */
	if (tt < 0 || !gmtime_r(&tt, &tm) ||
	    !strftime(buf, len, "%Y-%m-%dT%H:%M:%SZ", &tm))
		snprintf(buf, len, "?");
}

/*
 * The state file is trusted only in a directory that is ours alone; a file
 * named with --file must still be ours (see enum sw_read_mode).
 */
static enum sw_read_mode read_mode(const struct sw_opts *o)
{
	return o->file ? SW_READ_OWNED : SW_READ_STATE;
}

/*
 * Load the existing file at path, if any. Returns SW_EXIT_OK with
 * *have = true and *f filled when it is valid and made for this chip;
 * SW_EXIT_OK with *have = false when it is missing or not usable (why
 * says which); an error only when it must not be touched at all. errno_out
 * receives the errno of a failed open.
 */
static int load_existing(const struct sw_opts *o, const char *path,
			 const struct sw_chip_info *chip, struct sw_file *f,
			 bool *have, char *why, size_t why_len, int *errno_out,
			 struct sw_err *e)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	enum sw_file_check c;
	struct sw_err rerr;
	char detail[160];
	size_t len;
	int ret;

	*have = false;
	why[0] = '\0';
	sw_err_clear(&rerr);
	ret = sw_file_read(path, read_mode(o), buf, &len, errno_out, &rerr);
	if (ret == SW_EXIT_NOFILE)
		return SW_EXIT_OK;
	if (ret)
		return sw_err_set(e, rerr.code, "%s", rerr.msg);
	c = sw_file_decode(buf, len, f, detail, sizeof(detail));
	if (c == SW_CHECK_OK && chip)
		c = sw_file_match_chip(f, chip, detail, sizeof(detail));
	if (c != SW_CHECK_OK) {
		snprintf(why, why_len, "%s (%s)", sw_check_name(c), detail);
		return SW_EXIT_OK;
	}
	*have = true;
	return SW_EXIT_OK;
}

static bool exists(const char *path)
{
	struct stat st;

	return lstat(path, &st) == 0;
}

/* STATE_DIR/KEY.ws for a legacy key, or false when there is none. */
static bool legacy_path(const struct sw_opts *o, const struct sw_backend *b,
			int i, char *out, size_t len)
{
	const char *k = b->legacy_key[i];

	if (!k[0] || !strcmp(k, b->key))
		return false;
	snprintf(out, len, "%s/%s.ws", o->state_dir, k);
	return exists(out);
}

/*
 * Earlier versions keyed files by udev's ID_PATH or the I2C client's
 * name: move a file saved under one of those to the new key, once. Only the commands
 * that write the state directory do; a failure is reported and the file
 * is left where it is (it cannot be lost).
 */
static void migrate_legacy(const struct sw_backend *b, const struct sw_opts *o,
			   struct sw_env *env)
{
	char path[4096], old[4096];
	struct sw_err me;
	int i;

	if (o->file)
		return;
	sw_file_path(o, b, path, sizeof(path));
	if (exists(path))
		return;
	for (i = 0; i < SW_NLEGACY; i++) {
		if (!legacy_path(o, b, i, old, sizeof(old)))
			continue;
		sw_err_clear(&me);
		if (sw_file_rename(old, path, false, &me))
			sw_note(env, "warning: not migrating %s to %s: %s", old,
				path, me.msg);
		else
			sw_note(env, "migrated %s to %s (the key of %s is now %s)",
				old, path, b->name, b->key);
		return;
	}
}

/* The accel offsets of a blob (parameters 27..29) in LSB. */
static void blob_offsets(const uint8_t *blob, int lsb[3])
{
	int k;

	for (k = 0; k < 3; k++)
		lsb[k] = sw_g_to_lsb(sw_blob_param(blob, SW_PARAM_ACCEL_X + k));
}

/*
 * See struct sw_policy_in. Zero is what a chip holds from power-on until a
 * restore: a chip that was not restored must not overwrite saved offsets.
 */
static bool offsets_differ(const int chip[3], bool have_old,
			   const struct sw_file *old)
{
	static const int zero[3];
	int file[3];

	if (!memcmp(chip, zero, sizeof(zero)))
		return false;
	if (!have_old)
		return true;
	blob_offsets(old->payload, file);
	return memcmp(chip, file, sizeof(file)) != 0;
}

/*
 * The policy's answer for a calibration state, against the file at path
 * it would replace. The chip's accel offsets come from blob, or when it is
 * NULL from the driver's copy (no transfer); without blob the magnetometer
 * coefficients are not compared. chip receives the chip's identity, old
 * the file (when *what is SW_SAVE_OFFSETS), oldwhy why an existing file is
 * unusable ("" when it is fine or missing).
 */
static int policy_for(struct sw_backend *b, const struct sw_opts *o,
		      const struct sw_cal_state *cs, const uint8_t *blob,
		      struct sw_chip_info *chip, const char *path,
		      struct sw_file *old, enum sw_save_what *what, char *why,
		      size_t why_len, char *oldwhy, size_t oldwhy_len,
		      struct sw_err *e)
{
	struct sw_policy_in pin = { 0 };
	char old_desc[96] = "";
	struct sw_err lerr;
	int ret, lsb[3];

	ret = b->ops->chip_info(b, chip, e);
	if (ret)
		return ret;
	sw_err_clear(&lerr);
	memset(old, 0, sizeof(*old));
	ret = load_existing(o, path, chip, old, &pin.have_old, oldwhy,
			    oldwhy_len, NULL, &lerr);
	/* A missing state directory is created by the write. */
	if (ret && ret != SW_EXIT_STATEDIR)
		return sw_err_set(e, ret, "%s", lerr.msg);

	pin.mag_moved = -1;
	if (blob) {
		blob_offsets(blob, lsb);
		pin.offsets_differ = offsets_differ(lsb, pin.have_old, old);
		if (pin.have_old)
			pin.mag_moved = sw_params_moved(blob, old->payload,
							SW_PARAM_MAG_FIRST,
							SW_PARAM_MAG_LAST);
	} else {
		sw_err_clear(&lerr);
		ret = b->ops->accel_offset_get(b, lsb, &lerr);
		/* Offsets the driver cannot tell are left to the next save. */
		if (ret == SW_EXIT_DEVICE)
			return sw_err_set(e, ret, "%s", lerr.msg);
		pin.offsets_differ = !ret &&
				     offsets_differ(lsb, pin.have_old, old);
	}
	if (pin.have_old) {
		sw_file_describe(old, old_desc, sizeof(old_desc));
		pin.old_level = sw_file_level(old);
		pin.old_has_score = old->judgement == SW_JUDGED_SCORE;
		pin.old_score_raw = old->score_raw;
	}
	pin.old_desc = old_desc;
	pin.level = cs->level;
	pin.has_score = cs->has_score;
	pin.score_raw = cs->score_raw;
	pin.max_score = o->max_score;
	pin.force = o->force;
	pin.improve_only = o->improve_only;
	pin.margin = o->margin;
	*what = sw_policy_save(&pin, why, why_len);
	return SW_EXIT_OK;
}

int sw_save_wanted(struct sw_backend *b, const struct sw_opts *o,
		   const struct sw_cal_state *cs, const uint8_t *blob,
		   bool *yes, char *why, size_t len, struct sw_err *e)
{
	enum sw_save_what what = SW_SAVE_NOTHING;
	struct sw_chip_info chip;
	char path[4096], oldwhy[256];
	struct sw_file old;
	int ret;

	sw_file_path(o, b, path, sizeof(path));
	ret = policy_for(b, o, cs, blob, &chip, path, &old, &what, why, len,
			 oldwhy, sizeof(oldwhy), e);
	*yes = !ret && what != SW_SAVE_NOTHING;
	return ret;
}

/*
 * Take the lock of path's writers, waiting for another one at most
 * SW_LOCK_WAIT_MS. Returns the descriptor that holds it, or an exit code
 * negated.
 */
static int writers_lock(const struct sw_opts *o, struct sw_env *env,
			const char *path, struct sw_err *e)
{
	uint64_t start = env->now_ms(env->clk);
	char lock[4400];
	int fd;

	fd = sw_file_lock_open(path, !o->file, e);
	if (fd < 0)
		return fd;
	while (!sw_file_lock_try(fd)) {
		if (env->now_ms(env->clk) - start >= SW_LOCK_WAIT_MS) {
			close(fd);
			sw_file_lock_name(path, lock, sizeof(lock));
			return -sw_err_set(e, SW_EXIT_IO,
					   "%s: another writer of %s (watch, save, calibrate, accel-cal or restore) has held it for %d s; not writing",
					   lock, path, SW_LOCK_WAIT_MS / 1000);
		}
		env->sleep_ms(env->clk, 50);
	}
	return fd;
}

/*
 * The file the driver restores at probe (caldata.h), kept equal to the
 * state file's payload: only for the state file (not --file's), only with
 * the driver. A failure is a warning, not the command's: the state file
 * stands, and the restore after probe (the unit, the udev rule) still
 * brings it back.
 */
static void caldata_keep(const struct sw_backend *b, const struct sw_opts *o,
			 struct sw_env *env, const struct sw_chip_info *chip,
			 const uint8_t *payload)
{
	struct sw_err ce;

	if (o->file || !b->client[0])
		return;
	sw_err_clear(&ce);
	if (sw_caldata_write(o->state_dir, chip, b->client, payload, NULL, &ce))
		sw_note(env, "warning: %s; the driver cannot restore this calibration at probe, the restore after it still does",
			ce.msg);
}

/* The payload and header to write for the policy's answer. */
static void new_file(enum sw_save_what what, const struct sw_cal_state *cs,
		     const uint8_t *blob, const struct sw_file *old,
		     struct sw_file *nf)
{
	int k;

	nf->version = SW_FILE_VERSION;
	if (what == SW_SAVE_OFFSETS) {
		/* A version 1 file's header in version 2's terms. */
		nf->state = sw_file_level(old);
		nf->judgement = old->judgement;
		nf->score_raw = old->score_raw;
		memcpy(nf->payload, old->payload, SW_BLOB_SIZE);
		for (k = 0; k < 3; k++)
			sw_blob_set_param(nf->payload, SW_PARAM_ACCEL_X + k,
					  sw_blob_param(blob,
							SW_PARAM_ACCEL_X + k));
		return;
	}
	nf->state = cs->level;
	nf->judgement = cs->has_score ? SW_JUDGED_SCORE : SW_JUDGED_STABLE;
	nf->score_raw = cs->has_score ? cs->score_raw : 0;
	memcpy(nf->payload, blob, SW_BLOB_SIZE);
}

/* Under the writers' lock: the policy's look at the file, then the write. */
static int save_locked(struct sw_backend *b, const struct sw_opts *o,
		       struct sw_env *env, const struct sw_cal_state *cs,
		       const uint8_t *blob, const char *path, bool *saved,
		       struct sw_err *e)
{
	uint8_t out[SW_FILE_SIZE];
	enum sw_save_what what = SW_SAVE_NOTHING;
	char why[512], oldwhy[256];
	struct sw_file nf, old;
	int ret, lsb[3];

	migrate_legacy(b, o, env);
	memset(&nf, 0, sizeof(nf));
	ret = policy_for(b, o, cs, blob, &nf.chip, path, &old, &what, why,
			 sizeof(why), oldwhy, sizeof(oldwhy), e);
	if (ret)
		return ret;
	/* The policy saying no is the policy working: not a failure. */
	if (what == SW_SAVE_NOTHING) {
		sw_note(env, "not saving %s calibration to %s: %s", b->name,
			path, why);
		return SW_EXIT_OK;
	}
	if (oldwhy[0])
		sw_note(env, "replacing unusable %s: %s", path, oldwhy);
	new_file(what, cs, blob, &old, &nf);
	nf.saved_at = env->wall_s(env->clk);
	sw_file_encode(&nf, out);
	ret = sw_file_write_atomic(path, out, sizeof(out), !o->file, e);
	if (ret)
		return ret;
	caldata_keep(b, o, env, &nf.chip, nf.payload);
	blob_offsets(blob, lsb);
	if (what == SW_SAVE_OFFSETS)
		sw_note(env, "saved %s accel offsets %d %d %d LSB to %s: %s",
			b->name, lsb[0], lsb[1], lsb[2], path, why);
	else
		sw_note(env, "saved %s calibration to %s: %s", b->name, path,
			why);
	*saved = true;
	return SW_EXIT_OK;
}

int sw_save_snapshot(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, const struct sw_cal_state *cs,
		     const uint8_t *blob, bool *saved, struct sw_err *e)
{
	char path[4096], why[256];
	bool wrote = false;
	int bad, ret, lock;

	if (saved)
		*saved = false;
	if (!sw_cal_state_check(cs, why, sizeof(why)))
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: %s, read from the chip: not saving",
				  b->name, why);
	bad = sw_blob_nonfinite(blob);
	if (bad)
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: parameter %d (%s) read from the chip is not a finite number; not saving",
				  b->name, bad, sw_param_name(bad));
	sw_file_path(o, b, path, sizeof(path));
	lock = writers_lock(o, env, path, e);
	if (lock < 0)
		return -lock;
	ret = save_locked(b, o, env, cs, blob, path, &wrote, e);
	close(lock);
	if (saved)
		*saved = wrote;
	return ret;
}

/* Under the writers' lock: the import policy's look at the file, the write. */
static int import_locked(struct sw_backend *b, const struct sw_opts *o,
			 struct sw_env *env, const struct sw_board_cal *cal,
			 const char *path, struct sw_err *e)
{
	struct sw_policy_in pin = { 0 };
	uint8_t out[SW_FILE_SIZE];
	char why[512], oldwhy[256], old_desc[96] = "";
	struct sw_file nf, old;
	struct sw_err lerr;
	int ret;

	migrate_legacy(b, o, env);
	memset(&nf, 0, sizeof(nf));
	ret = b->ops->chip_info(b, &nf.chip, e);
	if (ret)
		return ret;
	sw_err_clear(&lerr);
	ret = load_existing(o, path, &nf.chip, &old, &pin.have_old, oldwhy,
			    sizeof(oldwhy), NULL, &lerr);
	/* A missing state directory is created by the write. */
	if (ret && ret != SW_EXIT_STATEDIR)
		return sw_err_set(e, ret, "%s", lerr.msg);
	if (pin.have_old)
		sw_file_describe(&old, old_desc, sizeof(old_desc));
	pin.old_desc = old_desc;
	pin.force = o->force;
	if (!sw_policy_import(&pin, why, sizeof(why))) {
		sw_note(env, "not importing the board's calibration for %s to %s: %s",
			b->name, path, why);
		return SW_EXIT_OK;
	}
	if (oldwhy[0])
		sw_note(env, "replacing unusable %s: %s", path, oldwhy);
	/*
	 * The block records no level or score: judgement none. Restore does
	 * not wait for a level, and save, watch and calibrate replace it
	 * with any stable calibration (by either rule: it is not stable).
	 */
	nf.version = SW_FILE_VERSION;
	nf.judgement = SW_JUDGED_NONE;
	nf.saved_at = env->wall_s(env->clk);
	memcpy(nf.payload, cal->blob, SW_BLOB_SIZE);
	sw_file_encode(&nf, out);
	ret = sw_file_write_atomic(path, out, sizeof(out), !o->file, e);
	if (ret)
		return ret;
	caldata_keep(b, o, env, &nf.chip, nf.payload);
	sw_note(env, "imported %s's calibration from the board's EEPROM (%s layout, parameters at 0x%04x) to %s: %s",
		b->name, sw_board_layout_name(cal->layout), cal->params_at,
		path, why);
	return SW_EXIT_OK;
}

/* The utilities' accel cal is reported, not imported (see the man page). */
static void note_board_accel(struct sw_env *env, const struct sw_board_cal *cal)
{
	if (!cal->accel_present) {
		sw_note(env, "the board holds no accel calibration");
		return;
	}
	sw_note(env, "the board's accel calibration (max/min LSB: x %d/%d, y %d/%d, z %d/%d)%s is not imported: the utilities apply it through registers of their firmware, not through warm-start parameters 27-29; run accel-cal for this tool's offsets",
		cal->acc_max[0], cal->acc_min[0], cal->acc_max[1],
		cal->acc_min[1], cal->acc_max[2], cal->acc_min[2],
		cal->accel_in_range ? "" :
		" is out of the utility's own bounds (1800..2240 LSB) and");
}

int sw_cmd_import_board(struct sw_backend *b, const struct sw_opts *o,
			struct sw_env *env, struct sw_err *e)
{
	struct sw_board_cal cal;
	enum sw_board_check c;
	struct sw_err rerr;
	char path[4096], detail[300];
	uint8_t *img;
	size_t len;
	int ret, lock;

	img = malloc(SW_BOARD_EEPROM_SIZE + 1);
	if (!img)
		return sw_err_set(e, SW_EXIT_OSERR, "out of memory");
	/*
	 * The image the administrator names, as show reads a file: at24's
	 * nvmem file lies under a symlinked directory. What it holds is
	 * checked below before anything is written.
	 */
	sw_err_clear(&rerr);
	ret = sw_file_read_max(o->image, SW_READ_ANY, img, SW_BOARD_EEPROM_SIZE,
			       &len, NULL, &rerr);
	if (ret == SW_EXIT_NOFILE)
		ret = sw_err_set(e, ret, "EEPROM image %s does not exist",
				 o->image);
	else if (ret)
		ret = sw_err_set(e, rerr.code, "%s", rerr.msg);
	if (!ret) {
		c = sw_board_parse(img, len, o->layout, &cal, detail,
				   sizeof(detail));
		if (c != SW_BOARD_OK)
			ret = sw_err_set(e, SW_EXIT_FILE,
					 "%s: refused: %s (%s); nothing written",
					 o->image, sw_board_check_name(c),
					 detail);
	}
	free(img);
	if (ret)
		return ret;
	sw_file_path(o, b, path, sizeof(path));
	lock = writers_lock(o, env, path, e);
	if (lock < 0)
		return -lock;
	ret = import_locked(b, o, env, &cal, path, e);
	close(lock);
	if (!ret)
		note_board_accel(env, &cal);
	return ret;
}

/* The worse of two states: the lower level, or at one level the higher score. */
static const struct sw_cal_state *worse(const struct sw_cal_state *a,
					const struct sw_cal_state *b)
{
	if (b->level != a->level)
		return b->level < a->level ? b : a;
	if (a->has_score != b->has_score)
		return a->has_score ? b : a;
	return b->score_raw > a->score_raw ? b : a;
}

int sw_read_snapshot(struct sw_backend *b, struct sw_cal_state *cs,
		     uint8_t *blob, struct sw_err *e)
{
	struct sw_cal_state before, after;
	char why[160];
	int i, ret;

	ret = b->ops->cal_state(b, &before, e);
	ret = ret ? ret : b->ops->read_blob(b, blob, e);
	ret = ret ? ret : b->ops->cal_state(b, &after, e);
	if (ret)
		return ret;
	for (i = 0; i < 2; i++)
		if (!sw_cal_state_check(i ? &after : &before, why, sizeof(why)))
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: %s, read from the chip: not saving",
					  b->name, why);
	/*
	 * The blob must be judged by the state it was taken in: if the
	 * calibration changed under the read, judge by the worse of the
	 * two; stable means stable before and after.
	 */
	*cs = *worse(&before, &after);
	return SW_EXIT_OK;
}

int sw_save_now(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, bool *saved, struct sw_err *e)
{
	struct sw_cal_state cs;
	uint8_t blob[SW_BLOB_SIZE];
	int ret;

	if (saved)
		*saved = false;
	ret = sw_read_snapshot(b, &cs, blob, e);
	return ret ? ret : sw_save_snapshot(b, o, env, &cs, blob, saved, e);
}

int sw_cmd_save(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, struct sw_err *e)
{
	return sw_save_now(b, o, env, NULL, e);
}

/*
 * A state file that failed a check is kept for inspection under
 * KEY.ws.refused (replacing an older one), so that the next save can write
 * a good calibration in its place: under the writers' lock, and only while
 * it still holds the len bytes of buf that were refused (a save may have
 * replaced it meanwhile). A --file file is the user's: left alone.
 */
static void set_aside(const struct sw_opts *o, struct sw_env *env,
		      const char *path, const uint8_t *buf, size_t len,
		      char *note, size_t note_len)
{
	uint8_t now[SW_FILE_MAX_READ + 1];
	char aside[4200];
	struct sw_err me;
	size_t now_len;
	int lock;

	note[0] = '\0';
	if (o->file)
		return;
	snprintf(aside, sizeof(aside), "%s.refused", path);
	sw_err_clear(&me);
	lock = writers_lock(o, env, path, &me);
	if (lock < 0) {
		snprintf(note, note_len, "; could not move it aside: %s", me.msg);
		return;
	}
	if (sw_file_read(path, read_mode(o), now, &now_len, NULL, &me) ||
	    now_len != len || memcmp(now, buf, len))
		snprintf(note, note_len,
			 "; not moved aside: it changed meanwhile (a save replaced it?)");
	else if (sw_file_rename(path, aside, true, &me))
		snprintf(note, note_len, "; could not move it aside: %s", me.msg);
	else
		snprintf(note, note_len, "; moved aside to %s for inspection",
			 aside);
	close(lock);
}

/*
 * After a restore, or the finding that the driver did it: the driver's
 * file for the next probe, so that the first boot after an upgrade from a
 * version without it makes one. Under the writers' lock, and only while
 * the state file still holds the len bytes of buf that were restored: a
 * save may have replaced it (and the driver's file) meanwhile.
 */
static void restore_caldata(const struct sw_backend *b,
			    const struct sw_opts *o, struct sw_env *env,
			    const char *path, const uint8_t *buf, size_t len,
			    const struct sw_file *f)
{
	uint8_t now[SW_FILE_MAX_READ + 1];
	struct sw_err le;
	size_t now_len;
	int lock;

	if (o->file || !b->client[0])
		return;
	sw_err_clear(&le);
	lock = writers_lock(o, env, path, &le);
	if (lock < 0) {
		sw_note(env, "warning: %s; the driver's file for the restore at probe is not updated",
			le.msg);
		return;
	}
	if (!sw_file_read(path, read_mode(o), now, &now_len, NULL, &le) &&
	    now_len == len && !memcmp(now, buf, len))
		caldata_keep(b, o, env, &f->chip, f->payload);
	close(lock);
}

/*
 * restore --if-present through the driver: does the chip hold the file's
 * calibration already, restored by the driver at probe (status's
 * "restored" comparison)? A blob that cannot be read is no answer: the
 * restore goes on.
 */
static bool restored_at_probe(struct sw_backend *b, const struct sw_opts *o,
			      const struct sw_file *f)
{
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_err re;

	if (!o->if_present || !b->client[0])
		return false;
	sw_err_clear(&re);
	return !b->ops->read_blob(b, blob, &re) &&
	       !sw_blob_restored(blob, f->payload);
}

/*
 * The file's identity against the chip's: SW_EXIT_OK to go on (a match, or
 * --force, said), else refused with the file set aside.
 */
static int restore_match(const struct sw_opts *o, struct sw_env *env, const char *path,
			 const uint8_t *buf, size_t len, const struct sw_file *f,
			 const struct sw_chip_info *chip, struct sw_err *e)
{
	char detail[160], aside[4400];
	enum sw_file_check c;

	c = sw_file_match_chip(f, chip, detail, sizeof(detail));
	if (c == SW_CHECK_OK)
		return SW_EXIT_OK;
	if (!o->force) {
		set_aside(o, env, path, buf, len, aside, sizeof(aside));
		return sw_err_set(e, SW_EXIT_FILE,
				  "%s: refused: %s (%s): saved on another chip or firmware; the chip was not touched (--force restores anyway)%s",
				  path, sw_check_name(c), detail, aside);
	}
	sw_note(env, "warning: %s: %s (%s); restoring anyway (--force)",
		path, sw_check_name(c), detail);
	return SW_EXIT_OK;
}

/*
 * Write the file's blob. A driver that checks the identity itself
 * (checks_identity) is given the file's and refuses another chip's or
 * firmware's: only then is the chip's read (one more read of the blob),
 * to say which, and with --force the blob is written as the chip's.
 * f->chip becomes the identity written.
 */
static int restore_write(struct sw_backend *b, const struct sw_opts *o,
			 struct sw_env *env, const char *path,
			 const uint8_t *buf, size_t len, struct sw_file *f,
			 struct sw_err *e)
{
	struct sw_chip_info chip;
	struct sw_err we;
	int ret;

	sw_err_clear(&we);
	ret = b->ops->write_blob(b, &f->chip, f->payload, &we);
	if (ret != SW_EXIT_FILE || !b->checks_identity)
		return ret ? sw_err_set(e, ret, "%s", we.msg) : SW_EXIT_OK;
	ret = b->ops->chip_info(b, &chip, e);
	ret = ret ? ret : restore_match(o, env, path, buf, len, f, &chip, e);
	if (ret)
		return ret;
	/* The tool's check passed (it leaves RevisionID out) or --force */
	if (!memcmp(&chip, &f->chip, sizeof(chip)))
		return sw_err_set(e, SW_EXIT_FILE, "%s", we.msg);
	f->chip = chip;
	return b->ops->write_blob(b, &f->chip, f->payload, e);
}

int sw_cmd_restore(struct sw_backend *b, const struct sw_opts *o,
		   struct sw_env *env, struct sw_err *e)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	struct sw_chip_info chip;
	struct sw_cal_state cs;
	enum sw_file_check c;
	struct sw_err rerr;
	char path[4096], detail[160], aside[4400], saved[96], now[32] = "";
	struct sw_file f;
	uint64_t start;
	size_t len;
	int ret;

	migrate_legacy(b, o, env);
	sw_file_path(o, b, path, sizeof(path));
	sw_err_clear(&rerr);
	ret = sw_file_read(path, read_mode(o), buf, &len, NULL, &rerr);
	if (ret == SW_EXIT_NOFILE && o->if_present) {
		sw_note(env, "no saved calibration for %s (%s); nothing to restore",
			b->name, path);
		return SW_EXIT_OK;
	}
	if (ret == SW_EXIT_NOFILE)
		return sw_err_set(e, SW_EXIT_NOFILE,
				  "no saved calibration for %s: %s does not exist",
				  b->name, path);
	if (ret)
		return sw_err_set(e, rerr.code, "%s", rerr.msg);
	c = sw_file_decode(buf, len, &f, detail, sizeof(detail));
	if (c != SW_CHECK_OK) {
		set_aside(o, env, path, buf, len, aside, sizeof(aside));
		return sw_err_set(e, SW_EXIT_FILE,
				  "%s: refused: %s (%s); the chip was not touched%s",
				  path, sw_check_name(c), detail, aside);
	}
	/* A driver that checks the identity does it in the write below */
	if (!b->checks_identity) {
		ret = b->ops->chip_info(b, &chip, e);
		if (ret)
			return ret;
		c = sw_file_match_chip(&f, &chip, detail, sizeof(detail));
		ret = restore_match(o, env, path, buf, len, &f, &chip, e);
		if (ret)
			return ret;
	}
	if (c == SW_CHECK_OK && restored_at_probe(b, o, &f)) {
		sw_note(env, "%s: already restored at probe: it holds the calibration of %s (parameters %d-%d and %d-%d within %.1f %%); nothing written",
			b->name, path, SW_PARAM_MAG_FIRST, SW_PARAM_MAG_LAST,
			SW_PARAM_ACCEL_X, SW_PARAM_ACCEL_X + 2,
			SW_PARAM_TOLERANCE * 100);
		restore_caldata(b, o, env, path, buf, len, &f);
		return SW_EXIT_OK;
	}
	ret = restore_write(b, o, env, path, buf, len, &f, e);
	if (ret)
		return ret;

	/*
	 * The chip needs a moment to take the coefficients in. A file saved
	 * stable brings CalibStable back at once: level 3 counts too (a
	 * magnetic transient now says nothing about the coefficients). A
	 * file saved for its accel offsets before the calibration was
	 * stable, or imported, cannot bring it.
	 */
	sw_file_describe(&f, saved, sizeof(saved));
	start = env->now_ms(env->clk);
	for (;;) {
		ret = b->ops->cal_state(b, &cs, e);
		if (ret)
			return ret;
		if (!sw_cal_state_check(&cs, detail, sizeof(detail)))
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: wrote %s, then read from the chip: %s",
					  b->name, path, detail);
		if (cs.level >= SW_LEVEL_TRANSIENT ||
		    sw_file_level(&f) != SW_LEVEL_STABLE)
			break;
		if (env->now_ms(env->clk) - start >= RESTORE_SETTLE_MS)
			return sw_err_set(e, SW_EXIT_CAL,
					  "%s: wrote %s (%s) but the calibration level is %d (%s), not 4 (stable)",
					  b->name, path, saved, cs.level,
					  sw_level_name(cs.level));
		env->sleep_ms(env->clk, RESTORE_POLL_MS);
	}
	if (cs.has_score)
		snprintf(now, sizeof(now), ", score %.3f%%",
			 sw_score_pct(cs.score_raw));
	sw_note(env, "restored %s calibration from %s: level %d (%s)%s (saved: %s)",
		b->name, path, cs.level, sw_level_name(cs.level), now, saved);
	restore_caldata(b, o, env, path, buf, len, &f);
	return SW_EXIT_OK;
}

void sw_json_str(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		unsigned char c = (unsigned char)*s;

		if (c == '"' || c == '\\')
			fprintf(f, "\\%c", c);
		else if (c < 0x20)
			fprintf(f, "\\u%04x", c);
		else
			fputc(c, f);
	}
	fputc('"', f);
}

/* How status names and shows each feature sensor. */
static const struct {
	const char *name;
	const char *unit;	/* ASCII: "C", not a degree sign */
	int decimals;		/* the firmware's resolution: 0.01 hPa, C, % */
} feature_kinds[SW_NFEATURES] = {
	[SW_FEATURE_PRESSURE] = { "pressure", "kPa", 3 },
	[SW_FEATURE_HUMIDITY] = { "humidity", "%", 2 },
	[SW_FEATURE_TEMP] = { "temperature", "C", 2 },
};

/* "firmware:" and "feature sensors:" lines; hi NULL: not read (why). */
static void status_hub_text(FILE *out, const struct sw_hub_info *hi,
			    const char *why)
{
	static const char *const source[] = {
		[SW_FW_EEPROM] = "from the board's EEPROM",
		[SW_FW_HOST] = "uploaded by the host",
	};
	unsigned int i;

	if (!hi) {
		fprintf(out, "firmware:            unknown (%s)\n", why);
		fprintf(out, "feature sensors:     unknown (%s)\n", why);
		return;
	}
	if (hi->fw_source == SW_FW_UNKNOWN)
		fprintf(out, "firmware:            unknown (%s)\n", hi->fw_why);
	else
		fprintf(out, "firmware:            %s\n", source[hi->fw_source]);
	if (!hi->nfeatures)
		fprintf(out, "feature sensors:     none\n");
	for (i = 0; i < hi->nfeatures; i++) {
		const struct sw_feature *f = &hi->features[i];

		fprintf(out, "%-21s%s ", i ? "" : "feature sensors:",
			feature_kinds[f->kind].name);
		if (f->have_value)
			fprintf(out, "%.*f %s", feature_kinds[f->kind].decimals,
				f->value, feature_kinds[f->kind].unit);
		else
			fprintf(out, "(no value while a buffer streams)");
		fprintf(out, " at %d Hz\n", f->rate_hz);
	}
}

/* "firmware_source" and "feature_sensors" members; null when unknown. */
static void status_hub_json(FILE *out, const struct sw_hub_info *hi)
{
	static const char *const source[] = {
		[SW_FW_UNKNOWN] = "null",
		[SW_FW_EEPROM] = "\"eeprom\"",
		[SW_FW_HOST] = "\"host\"",
	};
	unsigned int i;

	if (!hi) {
		fprintf(out, ",\"firmware_source\":null,\"feature_sensors\":null");
		return;
	}
	fprintf(out, ",\"firmware_source\":%s,\"feature_sensors\":[",
		source[hi->fw_source]);
	for (i = 0; i < hi->nfeatures; i++) {
		const struct sw_feature *f = &hi->features[i];

		fprintf(out, "%s{\"name\":\"%s\",\"value\":", i ? "," : "",
			feature_kinds[f->kind].name);
		if (f->have_value)
			fprintf(out, "%.*f", feature_kinds[f->kind].decimals,
				f->value);
		else
			fprintf(out, "null");
		fprintf(out, ",\"unit\":\"%s\",\"rate_hz\":%d}",
			feature_kinds[f->kind].unit, f->rate_hz);
	}
	fprintf(out, "]");
}

/* Does the chip hold the saved calibration? (status's "restored") */
enum restored {
	RESTORED_UNKNOWN,	/* no usable file, or the blob could not be read */
	RESTORED_NO,
	RESTORED_YES,
};

/*
 * Compare the chip's parameters 18..23 and 27..29 with the file's, within
 * the tolerance: one read of the blob, unless status read it (chip).
 * what says why, for the text.
 */
static enum restored status_restored(struct sw_backend *b,
				     const struct sw_file *f,
				     const uint8_t *chip, char *what,
				     size_t len)
{
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_err re;
	int n;

	sw_err_clear(&re);
	if (chip)
		memcpy(blob, chip, sizeof(blob));
	else if (b->ops->read_blob(b, blob, &re)) {
		snprintf(what, len, "unknown (%s)", re.msg);
		return RESTORED_UNKNOWN;
	}
	n = sw_blob_restored(blob, f->payload);
	if (!n) {
		snprintf(what, len,
			 "yes: the chip holds the saved calibration (parameters %d-%d and %d-%d within %.1f %%)",
			 SW_PARAM_MAG_FIRST, SW_PARAM_MAG_LAST,
			 SW_PARAM_ACCEL_X, SW_PARAM_ACCEL_X + 2,
			 SW_PARAM_TOLERANCE * 100);
		return RESTORED_YES;
	}
	snprintf(what, len,
		 "no: parameter %d (%s) is %.7g on the chip, %.7g in the file",
		 n, sw_param_name(n), (double)sw_blob_param(blob, n),
		 (double)sw_blob_param(f->payload, n));
	return RESTORED_NO;
}

/* What status found, for its text and JSON. */
struct status {
	struct sw_chip_info chip;
	bool have_chip;
	struct sw_err chip_err;
	/* the blob, when the identity came with it (checks_identity) */
	uint8_t blob[SW_BLOB_SIZE];
	bool have_blob;
	struct sw_hub_info hub;
	bool have_hub;
	struct sw_err hub_err;
	struct sw_cal_state cs;
	char path[4096];
	struct sw_file f;
	bool have_file;
	char file_why[4400];	/* !have_file: why */
	enum restored restored;
	char restored_what[640];
};

static void status_json(FILE *out, const struct sw_backend *b,
			const struct status *st)
{
	const struct sw_cal_state *cs = &st->cs;
	const struct sw_file *f = &st->f;
	static const char *const restored[] = {
		[RESTORED_UNKNOWN] = "null",
		[RESTORED_NO] = "false",
		[RESTORED_YES] = "true",
	};

	fprintf(out, "{\"device\":");
	sw_json_str(out, b->name);
	fprintf(out, ",\"backend\":\"%s\",\"key\":", b->kind);
	sw_json_str(out, b->key);
	if (st->have_chip)
		fprintf(out, ",\"product_id\":%u,\"revision_id\":%u,\"rom_version\":%u,\"ram_version\":%u",
			st->chip.product_id, st->chip.revision_id,
			st->chip.rom_version, st->chip.ram_version);
	status_hub_json(out, st->have_hub ? &st->hub : NULL);
	fprintf(out, ",\"level\":%d,\"level_name\":\"%s\"", cs->level,
		sw_level_name(cs->level));
	if (cs->has_score)
		fprintf(out, ",\"calibration_score\":%.3f,\"calibration_score_raw\":%u,\"gyro_bias_update\":%d,\"mag_calibration_update\":%d",
			sw_score_pct(cs->score_raw), cs->score_raw,
			cs->gyro_bias_update, cs->mag_cal_update);
	else
		fprintf(out, ",\"calibration_score\":null,\"calibration_score_raw\":null,\"gyro_bias_update\":null,\"mag_calibration_update\":null");
	fprintf(out, ",\"file\":");
	sw_json_str(out, st->path);
	if (!st->have_file) {
		fprintf(out, ",\"saved\":null,\"saved_problem\":");
		sw_json_str(out, st->file_why);
		fprintf(out, ",\"judgement\":null,\"restored\":null}\n");
		return;
	}
	fprintf(out, ",\"saved\":{\"version\":%d,\"level\":", f->version);
	if (f->judgement == SW_JUDGED_NONE)
		fprintf(out, "null,\"level_name\":null");
	else
		fprintf(out, "%d,\"level_name\":\"%s\"", sw_file_level(f),
			sw_level_name(sw_file_level(f)));
	if (f->judgement == SW_JUDGED_SCORE)
		fprintf(out, ",\"calibration_score\":%.3f,\"calibration_score_raw\":%u",
			sw_score_pct(f->score_raw), f->score_raw);
	else
		fprintf(out, ",\"calibration_score\":null,\"calibration_score_raw\":null");
	fprintf(out, ",\"saved_at\":%llu},\"judgement\":\"%s\",\"restored\":%s}\n",
		(unsigned long long)f->saved_at,
		sw_judgement_name(f->judgement), restored[st->restored]);
}

static void status_text(FILE *out, const struct sw_backend *b,
			const struct status *st)
{
	const struct sw_cal_state *cs = &st->cs;
	char desc[96], when[40];

	fprintf(out, "device:              %s (%s backend)\n", b->name, b->kind);
	fprintf(out, "key:                 %s\n", b->key);
	if (st->have_chip)
		fprintf(out, "chip:                ProductID 0x%02x, RevisionID 0x%02x, ROM 0x%04x, RAM 0x%04x\n",
			st->chip.product_id, st->chip.revision_id,
			st->chip.rom_version, st->chip.ram_version);
	else
		fprintf(out, "chip:                unknown (%s)\n", st->chip_err.msg);
	status_hub_text(out, st->have_hub ? &st->hub : NULL, st->hub_err.msg);
	fprintf(out, "calibration level:   %d (%s)\n", cs->level,
		sw_level_name(cs->level));
	if (cs->has_score) {
		fprintf(out, "calibration score:   %.3f%%\n",
			sw_score_pct(cs->score_raw));
		fprintf(out, "gyro bias update:    %d\n", cs->gyro_bias_update);
		fprintf(out, "mag cal update:      %d\n", cs->mag_cal_update);
	} else {
		fprintf(out, "calibration score:   not reported by this firmware (saved by the level alone)\n");
	}
	if (!st->have_file) {
		fprintf(out, "saved file:          %s: %s\n", st->path,
			st->file_why);
		return;
	}
	sw_file_describe(&st->f, desc, sizeof(desc));
	fmt_time(st->f.saved_at, when, sizeof(when));
	fprintf(out, "saved file:          %s: %s, saved %s\n", st->path, desc,
		when);
	fprintf(out, "restored:            %s\n", st->restored_what);
}

/*
 * The saved file: loaded into st, or why not. An error only for a file
 * root must not trust (see below).
 */
static int status_file(struct sw_backend *b, const struct sw_opts *o,
		       struct status *st, struct sw_err *e)
{
	char *why = st->file_why, old[4096];
	size_t len = sizeof(st->file_why);
	struct sw_err ferr;
	int ret, err = 0;

	sw_file_path(o, b, st->path, sizeof(st->path));
	sw_err_clear(&ferr);
	ret = load_existing(o, st->path, st->have_chip ? &st->chip : NULL,
			    &st->f, &st->have_file, why, len, &err, &ferr);
	/*
	 * The chip's attributes are world-readable, the state directory is
	 * root's: a user still sees the chip's part. Root is told of a state
	 * file it must not trust (exit status).
	 */
	if (ret && geteuid() != 0 &&
	    (ret == SW_EXIT_PERM || err == EACCES)) {
		snprintf(why, len, "needs root to read (%s)", ferr.msg);
		ret = SW_EXIT_OK;
	}
	if (ret == SW_EXIT_STATEDIR) {
		snprintf(why, len, "%s", ferr.msg);
		ret = SW_EXIT_OK;
	}
	if (ret)
		return sw_err_set(e, ret, "%s", ferr.msg);
	if (!st->have_file && !why[0] && !o->file &&
	    (legacy_path(o, b, 0, old, sizeof(old)) ||
	     legacy_path(o, b, 1, old, sizeof(old))))
		snprintf(why, len,
			 "none yet; %s (saved under an older key) moves here at the next restore or save",
			 old);
	if (!st->have_file && !why[0])
		snprintf(why, len, "no saved calibration yet");
	return SW_EXIT_OK;
}

int sw_cmd_status(struct sw_backend *b, const struct sw_opts *o,
		  struct sw_env *env, struct sw_err *e)
{
	struct status *st;
	int ret;

	st = calloc(1, sizeof(*st));
	if (!st)
		return sw_err_set(e, SW_EXIT_OSERR, "out of memory");
	ret = b->ops->cal_state(b, &st->cs, e);
	if (ret)
		goto out;
	sw_err_clear(&st->chip_err);
	/*
	 * Where the identity is in the blob's header, one read of the blob
	 * serves the identity and the comparison with the saved file.
	 */
	if (b->checks_identity)
		st->have_blob = !b->ops->read_blob(b, st->blob, &st->chip_err);
	st->have_chip = (!b->checks_identity || st->have_blob) &&
			b->ops->chip_info(b, &st->chip, &st->chip_err) ==
			SW_EXIT_OK;
	sw_err_clear(&st->hub_err);
	st->have_hub = b->ops->hub_info(b, &st->hub, &st->hub_err) ==
		       SW_EXIT_OK;
	ret = status_file(b, o, st, e);
	if (ret)
		goto out;
	/* Only a file made for this chip can have been restored into it. */
	if (st->have_file && st->have_chip)
		st->restored = status_restored(b, &st->f,
					       st->have_blob ? st->blob : NULL,
					       st->restored_what,
					       sizeof(st->restored_what));
	else
		snprintf(st->restored_what, sizeof(st->restored_what),
			 "unknown (%s)", st->chip_err.msg);
	if (o->json)
		status_json(env->out, b, st);
	else
		status_text(env->out, b, st);
out:
	free(st);
	return ret;
}

/* key --json: device, backend, key, unit (null: too long), file. */
static void key_json(FILE *out, const struct sw_backend *b,
		     const struct sw_opts *o, const char *unit)
{
	char path[4096];

	sw_file_path(o, b, path, sizeof(path));
	fprintf(out, "{\"device\":");
	sw_json_str(out, b->name);
	fprintf(out, ",\"backend\":\"%s\",\"key\":", b->kind);
	sw_json_str(out, b->key);
	fprintf(out, ",\"unit\":");
	if (unit)
		sw_json_str(out, unit);
	else
		fprintf(out, "null");
	fprintf(out, ",\"file\":");
	sw_json_str(out, path);
	fprintf(out, "}\n");
}

int sw_cmd_key(struct sw_backend *b, const struct sw_opts *o,
	       struct sw_env *env, struct sw_err *e)
{
	char unit[SW_KEY_MAX * 4];
	bool unit_ok = sw_key_unit_escape(b->key, unit, sizeof(unit)) &&
		       strlen(unit) <= 255 - strlen("sentral-warmstart-restore@.service");

	if (o->json) {
		key_json(env->out, b, o, unit_ok ? unit : NULL);
		return SW_EXIT_OK;
	}
	if (!o->udev) {
		fprintf(env->out, "%s\n", b->key);
		return SW_EXIT_OK;
	}
	if (!unit_ok)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: key %s is too long for a systemd unit name",
				  b->name, b->key);
	fprintf(env->out, "SENTRAL_WARMSTART_KEY=%s\nSENTRAL_WARMSTART_UNIT=%s\n",
		b->key, unit);
	return SW_EXIT_OK;
}

/*
 * show --json: one object, the members status --json gives a saved file
 * (its "saved" object) and the header and parameters show prints.
 */
static void show_json(FILE *out, const char *path, const struct sw_file *f,
		      const uint8_t *buf, size_t len)
{
	int n;

	fprintf(out, "{\"file\":");
	sw_json_str(out, path);
	fprintf(out, ",\"version\":%d,\"size\":%zu,\"crc32\":%u", f->version,
		len, sw_get_le32(buf + SW_FILE_SIZE - 4));
	fprintf(out, ",\"product_id\":%u,\"revision_id\":%u,\"rom_version\":%u,\"ram_version\":%u",
		f->chip.product_id, f->chip.revision_id, f->chip.rom_version,
		f->chip.ram_version);
	if (f->version == SW_FILE_VERSION_1)
		fprintf(out, ",\"status\":%d", f->state);
	else
		fprintf(out, ",\"status\":null");
	if (f->judgement == SW_JUDGED_NONE)
		fprintf(out, ",\"level\":null,\"level_name\":null");
	else
		fprintf(out, ",\"level\":%d,\"level_name\":\"%s\"",
			sw_file_level(f), sw_level_name(sw_file_level(f)));
	fprintf(out, ",\"judgement\":\"%s\"", sw_judgement_name(f->judgement));
	if (f->judgement == SW_JUDGED_SCORE)
		fprintf(out, ",\"calibration_score\":%.3f,\"calibration_score_raw\":%u",
			sw_score_pct(f->score_raw), f->score_raw);
	else
		fprintf(out, ",\"calibration_score\":null,\"calibration_score_raw\":null");
	fprintf(out, ",\"saved_at\":%llu,\"parameters\":[",
		(unsigned long long)f->saved_at);
	for (n = 1; n <= SW_NPARAMS; n++) {
		/* 9 digits give a float32 back exactly; the file holds no NaN. */
		fprintf(out, "%s{\"number\":%d,\"name\":\"%s\",\"raw\":%u,\"value\":%.9g",
			n > 1 ? "," : "", n, sw_param_name(n),
			sw_get_le32(f->payload + 4 * (n - 1)),
			(double)sw_blob_param(f->payload, n));
		if (n >= SW_PARAM_ACCEL_X && n < SW_PARAM_ACCEL_X + 3)
			fprintf(out, ",\"accel_lsb\":%d",
				sw_g_to_lsb(sw_blob_param(f->payload, n)));
		fputc('}', out);
	}
	fprintf(out, "]}\n");
}

int sw_cmd_show(const struct sw_opts *o, struct sw_env *env,
		struct sw_err *e)
{
	static const char *const judgements[] = {
		[SW_JUDGED_NONE] = "none (imported from the board's EEPROM: no level or score)",
		[SW_JUDGED_SCORE] = "score (the application note's score)",
		[SW_JUDGED_STABLE] = "stable (the level alone: the firmware reports no score)",
	};
	uint8_t buf[SW_FILE_MAX_READ + 1];
	enum sw_file_check c;
	char detail[160], when[40];
	struct sw_file f;
	FILE *out = env->out;
	size_t len;
	int n;

	/* Only reading: following a symlink the user named is harmless. */
	if (sw_file_read(o->file, SW_READ_ANY, buf, &len, NULL, e))
		return e->code;
	c = sw_file_decode(buf, len, &f, detail, sizeof(detail));
	if (c != SW_CHECK_OK)
		return sw_err_set(e, SW_EXIT_FILE, "%s: refused: %s (%s)",
				  o->file, sw_check_name(c), detail);
	if (o->json) {
		show_json(out, o->file, &f, buf, len);
		return SW_EXIT_OK;
	}
	fmt_time(f.saved_at, when, sizeof(when));
	fprintf(out, "file:                %s\n", o->file);
	fprintf(out, "format:              %s version %d, %zu bytes, CRC-32 0x%08x ok\n",
		SW_FILE_MAGIC, f.version, len,
		sw_get_le32(buf + SW_FILE_SIZE - 4));
	fprintf(out, "ProductID:           0x%02x\n", f.chip.product_id);
	fprintf(out, "RevisionID:          0x%02x\n", f.chip.revision_id);
	fprintf(out, "ROM version:         0x%04x\n", f.chip.rom_version);
	fprintf(out, "RAM version:         0x%04x\n", f.chip.ram_version);
	if (f.version == SW_FILE_VERSION_1)
		fprintf(out, "calibration status:  %d (%s)\n", f.state,
			f.state == 3 ? "complete: stable" : "not stable");
	else if (f.judgement != SW_JUDGED_NONE)
		fprintf(out, "calibration level:   %d (%s)\n", f.state,
			sw_level_name(f.state));
	fprintf(out, "judgement:           %s\n", judgements[f.judgement]);
	if (f.judgement == SW_JUDGED_SCORE)
		fprintf(out, "calibration score:   %.3f%% (raw 0x%04x)\n",
			sw_score_pct(f.score_raw), f.score_raw);
	fprintf(out, "saved at:            %s (%llu)\n", when,
		(unsigned long long)f.saved_at);
	fprintf(out, "parameters:\n");
	for (n = 1; n <= SW_NPARAMS; n++) {
		uint32_t raw = sw_get_le32(f.payload + 4 * (n - 1));

		fprintf(out, "  %2d  %-11s 0x%08x  %.7g", n, sw_param_name(n),
			raw, (double)sw_blob_param(f.payload, n));
		if (n >= SW_PARAM_ACCEL_X && n < SW_PARAM_ACCEL_X + 3)
			fprintf(out, " g (accel %c offset, %d LSB)",
				'X' + n - SW_PARAM_ACCEL_X,
				sw_g_to_lsb(sw_blob_param(f.payload, n)));
		fputc('\n', out);
	}
	return SW_EXIT_OK;
}
