"""The Green's functions' cache: entries read and written so that a folder
others can write, or one that is read-only, full or holds bad entries,
costs speed only, never a wrong result, a hang or another's file.

An entry KEY.npz (KEY: responses.cache_key, a hash of everything that
enters the spectra) holds complex128 arrays of the shapes the caller
expects, and a `digest`: the SHA-256 of the key and the arrays' bytes.
Read: opened without following a link and without blocking (a FIFO),
a regular file only, its size and each member's size bounded by the
expected shapes before anything is decompressed or allocated, each
member's header checked for dtype and shape, the values finite, the
digest recomputed; and the entry must be this user's own (owner the
effective uid, no write bit for group or others): the digest finds damage
and entries written for another key, while another user who can write the
folder could recompute it for wrong data. A missing entry is a miss; a bad one a warning on
stderr and a miss (the caller computes and writes it again). Written:
into a new file made by mkstemp in the cache folder (never an existing
name, never through a link), then os.replace onto the entry's name; a
folder that cannot be made or written gives one warning per process and
the result uncached, and no temporary file is left behind.
"""
from __future__ import annotations

import hashlib
import os
import stat
import sys
import tempfile
import zipfile

import numpy as np

SLACK = 64 << 10  # bytes a member's and the archive's headers may add
_warned = set()


def warn(text, once=None):
    """A warning on stderr (once per process for the same `once`)."""
    if once is not None:
        if once in _warned:
            return
        _warned.add(once)
    print("green_soil: %s" % text, file=sys.stderr, flush=True)


def digest(key, arrays):
    """SHA-256 of the key and the arrays (name, dtype, shape, bytes), in order."""
    h = hashlib.sha256(key.encode())
    for name, a in arrays:
        a = np.ascontiguousarray(a)
        h.update(("%s|%s|%s|" % (name, a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return np.frombuffer(h.digest(), dtype=np.uint8)


def _member(zf, name, shape, dtype):
    """One array of the archive, its size bounded before it is read."""
    try:
        info = zf.getinfo(name + ".npy")
    except KeyError:
        raise ValueError("it has no %s" % name)
    nbytes = int(np.prod(shape, dtype=np.int64)) * np.dtype(dtype).itemsize
    if info.file_size > nbytes + SLACK:
        raise ValueError("its %s holds %d bytes, %d expected" % (name, info.file_size, nbytes))
    with zf.open(info) as m:
        version = np.lib.format.read_magic(m)
        read_header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                       else np.lib.format.read_array_header_2_0)
        got_shape, fortran, got_dtype = read_header(m)
        if tuple(got_shape) != tuple(shape) or got_dtype != np.dtype(dtype) or fortran:
            raise ValueError("its %s is %s %s, %s %s expected"
                             % (name, got_dtype, tuple(got_shape), np.dtype(dtype), tuple(shape)))
        data = m.read(nbytes + 1)
    if len(data) != nbytes:
        raise ValueError("its %s holds %d bytes, %d expected" % (name, len(data), nbytes))
    return np.frombuffer(data, dtype=dtype).reshape(shape).copy()


def load(path, key, expected):
    """The arrays {name: array} of the entry at path if it is good, for
    `expected` [(name, shape)] (complex128); None on a miss or a bad entry
    (warned)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except (FileNotFoundError, NotADirectoryError):  # a miss (no folder yet: one that cannot be
        return None  # made is warned about when the entry is written)
    except OSError as e:
        warn("the cached Green's functions %s cannot be read (%s); computed again"
             % (path, e.strerror or e))
        return None
    try:
        with os.fdopen(fd, "rb") as f:
            st = os.fstat(f.fileno())
            limit = sum(16 * int(np.prod(s, dtype=np.int64)) for _, s in expected) + 4 * SLACK
            if not stat.S_ISREG(st.st_mode):
                raise ValueError("it is not a regular file")
            if st.st_uid != os.geteuid() or st.st_mode & 0o022:
                # The digest finds damage, not a forger: whoever can write
                # the entry can recompute it, so only this user's own count.
                raise ValueError("it belongs to uid %d or others may write it (mode %o); only "
                                 "this user's own entries are used"
                                 % (st.st_uid, stat.S_IMODE(st.st_mode)))
            if st.st_size > limit:
                raise ValueError("it has %d bytes, at most %d expected" % (st.st_size, limit))
            with zipfile.ZipFile(f) as zf:
                names = sorted(zf.namelist())
                want = sorted([n + ".npy" for n, _ in expected] + ["digest.npy"])
                if names != want:
                    raise ValueError("it holds %s, not %s" % (names, want))
                out = [(n, _member(zf, n, s, np.complex128)) for n, s in expected]
                stored = _member(zf, "digest", (32,), np.uint8)
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as e:
        warn("the cached Green's functions %s are not usable (%s); computed again" % (path, e))
        return None
    for name, a in out:
        if not np.isfinite(a).all():
            warn("the cached Green's functions %s hold values that are not finite in %s; "
                 "computed again" % (path, name))
            return None
    if not np.array_equal(stored, digest(key, out)):
        warn("the cached Green's functions %s do not match their checksum (changed since they "
             "were written, or written for another key); computed again" % path)
        return None
    return dict(out)


def store(cache_dir, path, key, arrays):
    """Writes the entry [(name, array)] at path atomically; a folder that
    cannot be made or written costs the cache only (one warning)."""
    tmp = None
    try:
        os.makedirs(cache_dir, mode=0o700, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=cache_dir, prefix=".", suffix=".tmp.npz")
        with os.fdopen(fd, "wb") as f:
            np.savez(f, digest=digest(key, arrays), **dict(arrays))
        os.replace(tmp, path)
        tmp = None
    except OSError as e:
        warn("the Green's functions cannot be cached in %s (%s): computed without caching, "
             "which costs only time" % (cache_dir, e.strerror or e), once=cache_dir)
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
