/* file_io.c - whole-file reads and atomic image output. The temp file lives in the target's directory
 * so rename() stays on one file system and readers never see a half-written image. */
#include "file_io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int file_read_all(const char *path, char **data, size_t *len, lc_error *err)
{
    char *buf = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lc_fail(err, LC_E_FILE, "cannot open %s: %s", path, strerror(errno));
    errno = 0;
    if (fseek(fp, 0, SEEK_END) != 0)
        goto io_fail;
    long size = ftell(fp);
    if (size < 0 || fseek(fp, 0, SEEK_SET) != 0)
        goto io_fail;
    buf = malloc((size_t)size + 1);
    if (!buf) {
        fclose(fp);
        return lc_fail(err, LC_E_INTERNAL, "out of memory reading %s (%ld bytes)", path, size);
    }
    if (fread(buf, 1, (size_t)size, fp) != (size_t)size)
        goto io_fail;
    buf[size] = 0;
    fclose(fp);
    *data = buf;
    *len = (size_t)size;
    return LC_OK;
io_fail:
    /* ftell fails with ESPIPE on a directory or pipe; say so plainly. */
    lc_fail(err, LC_E_FILE, "cannot read %s: %s", path, errno ? strerror(errno) : "short read");
    free(buf);
    fclose(fp);
    return err->code;
}

int output_open(struct output_file *out, const char *path, lc_error *err)
{
    memset(out, 0, sizeof *out);
    out->path = path;
    if (strcmp(path, "-") == 0) {
        out->fp = tmpfile();
        if (!out->fp)
            return lc_fail(err, LC_E_FILE, "cannot create a temporary file: %s", strerror(errno));
        return LC_OK;
    }
    size_t n = strlen(path) + sizeof ".tmp.XXXXXX";
    out->tmp_path = malloc(n);
    if (!out->tmp_path)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    snprintf(out->tmp_path, n, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(out->tmp_path);
    if (fd < 0) {
        lc_fail(err, LC_E_FILE, "cannot write %s: %s", path, strerror(errno));
        goto fail;
    }
    /* mkstemp makes the file 0600; the image should get the permissions any new file would. */
    mode_t mask = umask(0);
    umask(mask);
    if (fchmod(fd, 0666 & ~mask) != 0) {
        lc_fail(err, LC_E_FILE, "cannot write %s: %s", path, strerror(errno));
        close(fd);
        unlink(out->tmp_path);
        goto fail;
    }
    out->fp = fdopen(fd, "wb");
    if (!out->fp) {
        lc_fail(err, LC_E_FILE, "cannot write %s: %s", path, strerror(errno));
        close(fd);
        unlink(out->tmp_path);
        goto fail;
    }
    return LC_OK;
fail:
    free(out->tmp_path);
    out->tmp_path = NULL;
    return err->code;
}

static int copy_to_stdout(FILE *fp, lc_error *err)
{
    char buf[65536];
    size_t n;
    rewind(fp);
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        if (fwrite(buf, 1, n, stdout) != n)
            return lc_fail(err, LC_E_FILE, "cannot write to standard output: %s", strerror(errno));
    if (ferror(fp) || fflush(stdout) != 0)
        return lc_fail(err, LC_E_FILE, "cannot write to standard output: %s", strerror(errno));
    return LC_OK;
}

int output_commit(struct output_file *out, lc_error *err)
{
    int rc = LC_OK;
    if (!out->tmp_path) {
        rc = copy_to_stdout(out->fp, err);
        output_abort(out);
        return rc;
    }
    int write_failed = fflush(out->fp) != 0 || ferror(out->fp);
    int saved = errno;
    if (fclose(out->fp) != 0 && !write_failed) {
        write_failed = 1;
        saved = errno;
    }
    out->fp = NULL;
    if (write_failed) {
        lc_fail(err, LC_E_FILE, "cannot write %s: %s", out->path, strerror(saved));
        goto fail;
    }
    if (rename(out->tmp_path, out->path) != 0) {
        lc_fail(err, LC_E_FILE, "cannot write %s: %s", out->path, strerror(errno));
        goto fail;
    }
    free(out->tmp_path);
    out->tmp_path = NULL;
    return LC_OK;
fail:
    output_abort(out);
    return err->code;
}

void output_abort(struct output_file *out)
{
    if (out->fp)
        fclose(out->fp);
    out->fp = NULL;
    if (out->tmp_path) {
        unlink(out->tmp_path);
        free(out->tmp_path);
        out->tmp_path = NULL;
    }
}
