"""FLINT's Calcium through ctypes: the library python-flint loads, struct layouts, signatures,
the one ``ca_ctx_t`` and the lock around every call (the layer below :mod:`lcs_exact.calcium`).

python-flint has no binding for Calcium, but the FLINT library it ships exports it; this module
loads that very library, declares the functions :mod:`lcs_exact.calcium` calls, and converts
FLINT's integers, strings and balls to Python's and python-flint's.

Layout
------
The struct layouts below are those of FLINT 3.6.0 on 64-bit Linux (``src/ca_types.h``,
``src/qqbar.h``, ``src/acb_types.h``, ``src/arb_types.h``, ``src/arf_types.h``,
``src/fmpz_types.h``, ``src/flint.h.in``; identical from 3.3.0 to the development head).
On first use they are checked against the library itself (sentinel-filled buffers around
``ca_ctx_init``, ``ca_init``, ``ca_i``, ``qqbar_init``, ``acb_init``); a mismatch makes
:func:`available` return False instead of risking memory corruption.
"""
from __future__ import annotations

import atexit
import contextlib
import ctypes
import threading
from pathlib import Path
from typing import Any

import flint
from flint import acb, arb, arf

__all__ = ["available", "backend", "isolated_backend", "find_library", "Backend", "self_check", "CTYPES", "CA_UNKNOWN", "CA_UNDEFINED", "CA_INF", "truth", "take_str", "fmpz_to_int", "acb_from_address",
           "TempFmpz", "CA_WORDS", "STRUCT_SIZES", "T_TRUE", "T_FALSE", "T_UNKNOWN", "c_ptr", "c_ulong",
           "FmpqStruct", "FmpzPolyStruct", "AcbStruct", "QqbarStruct", "qqbar_distinct_roots", "select_qqbar_root",
           "PREC_LIMIT_ALGEBRAIC"]

# ---------------------------------------------------------------------------------------------
# FLINT 3.6 struct layouts (64-bit).  fmpz is one slong; truth_t is an enum (int).
# ---------------------------------------------------------------------------------------------

_slong = ctypes.c_int64
c_ulong = ctypes.c_uint64
c_ptr = ctypes.c_void_p

T_TRUE, T_FALSE, T_UNKNOWN = 0, 1, 2              # gr_types.h: typedef enum {T_TRUE, T_FALSE, T_UNKNOWN}
CA_UNKNOWN, CA_UNDEFINED, CA_INF = 1, 2, 3     # ca.h: low bits of ca_struct.field for special values
_CA_OPT_PREC_LIMIT, _CA_OPT_QQBAR_DEG_LIMIT, _CA_OPT_LOW_PREC = 3, 4, 5


class FmpqStruct(ctypes.Structure):
    _fields_ = [("num", _slong), ("den", _slong)]


class FmpzPolyStruct(ctypes.Structure):
    _fields_ = [("coeffs", c_ptr), ("alloc", _slong), ("length", _slong)]


class _fmpq_poly(ctypes.Structure):
    _fields_ = [("coeffs", c_ptr), ("alloc", _slong), ("length", _slong), ("den", _slong)]


class _mag(ctypes.Structure):
    _fields_ = [("exp", _slong), ("man", c_ulong)]


class _arf(ctypes.Structure):
    _fields_ = [("exp", _slong), ("size", _slong), ("d", c_ulong * 2)]   # ARF_NOPTR_LIMBS = 2


class _arb(ctypes.Structure):
    _fields_ = [("mid", _arf), ("rad", _mag)]


class AcbStruct(ctypes.Structure):
    _fields_ = [("real", _arb), ("imag", _arb)]


class QqbarStruct(ctypes.Structure):
    _fields_ = [("poly", FmpzPolyStruct), ("enclosure", AcbStruct)]


class _lnf_elem(ctypes.Structure):
    _fields_ = [("num", _slong), ("den", _slong)]


class _qnf_elem(ctypes.Structure):
    _fields_ = [("num", _slong * 3), ("den", _slong)]


class _nf_elem(ctypes.Union):
    _fields_ = [("elem", _fmpq_poly), ("lelem", _lnf_elem), ("qelem", _qnf_elem)]


class _ca_elem(ctypes.Union):
    _fields_ = [("q", FmpqStruct), ("nf", _nf_elem), ("mpoly_q", c_ptr)]


class _ca(ctypes.Structure):
    _fields_ = [("field", c_ulong), ("elem", _ca_elem)]


class _ca_cache(ctypes.Structure):      # ca_ext_cache_struct and ca_field_cache_struct
    _fields_ = [("items", c_ptr), ("length", _slong), ("alloc", _slong),
                ("hash_size", _slong), ("hash_table", c_ptr)]


class _ca_ctx(ctypes.Structure):
    _fields_ = [("ext_cache", _ca_cache), ("field_cache", _ca_cache), ("field_qq", c_ulong),
                ("field_qq_i", c_ulong), ("mctx", c_ptr), ("mctx_len", _slong),
                ("options", ctypes.POINTER(_slong))]


#: sizeof() of each struct, as read in the FLINT 3.6 headers (checked at first use).
STRUCT_SIZES = {"fmpz": 8, "fmpq": 16, "fmpz_poly_struct": 24, "mag_struct": 16, "arf_struct": 32,
                "arb_struct": 48, "acb_struct": 96, "qqbar_struct": 120, "ca_struct": 40,
                "ca_ctx_struct": 120}
CTYPES = {"fmpz": _slong, "fmpq": FmpqStruct, "fmpz_poly_struct": FmpzPolyStruct, "mag_struct": _mag,
           "arf_struct": _arf, "arb_struct": _arb, "acb_struct": AcbStruct, "qqbar_struct": QqbarStruct,
           "ca_struct": _ca, "ca_ctx_struct": _ca_ctx}
CA_WORDS = 2 * STRUCT_SIZES["ca_struct"] // 8          # over-allocation: 2 x sizeof
_SENTINEL = 0xA5A5A5A5A5A5A5A5

# name: (restype, argtypes); pointers are passed as ints (addresses) or ctypes byref.
_P, _S, _I, _C = c_ptr, _slong, ctypes.c_int, ctypes.c_char_p
_SIGNATURES: dict[str, tuple[Any, list[Any]]] = {
    "ca_ctx_init": (None, [_P]), "ca_ctx_clear": (None, [_P]),
    "ca_init": (None, [_P, _P]), "ca_clear": (None, [_P, _P]), "ca_set": (None, [_P, _P, _P]),
    "ca_set_si": (None, [_P, _S, _P]),
    "ca_set_fmpq": (None, [_P, _P, _P]), "ca_set_qqbar": (None, [_P, _P, _P]),
    "ca_pi": (None, [_P, _P]), "ca_i": (None, [_P, _P]),
    "ca_neg": (None, [_P, _P, _P]), "ca_add": (None, [_P, _P, _P, _P]),
    "ca_sub": (None, [_P, _P, _P, _P]), "ca_mul": (None, [_P, _P, _P, _P]),
    "ca_inv": (None, [_P, _P, _P]), "ca_pow_si": (None, [_P, _P, _S, _P]),
    "ca_exp": (None, [_P, _P, _P]), "ca_log": (None, [_P, _P, _P]), "ca_sqrt": (None, [_P, _P, _P]),
    "ca_sin": (None, [_P, _P, _P]), "ca_cos": (None, [_P, _P, _P]), "ca_atan": (None, [_P, _P, _P]),
    "ca_acos": (None, [_P, _P, _P]), "ca_asin": (None, [_P, _P, _P]), "ca_re": (None, [_P, _P, _P]),
    "ca_im": (None, [_P, _P, _P]), "ca_conj": (None, [_P, _P, _P]), "ca_abs": (None, [_P, _P, _P]),
    "ca_check_is_zero": (_I, [_P, _P]), "ca_check_is_rational": (_I, [_P, _P]),
    "ca_check_is_real": (_I, [_P, _P]), "ca_check_gt": (_I, [_P, _P, _P]),
    "ca_get_fmpq": (_I, [_P, _P, _P]), "ca_get_acb": (None, [_P, _P, _S, _P]),
    "ca_get_acb_raw": (None, [_P, _P, _S, _P]),
    "ca_get_str": (_P, [_P, _P]), "ca_ctx_get_option": (_S, [_P, _S]),
    "ca_ctx_set_option": (None, [_P, _S, _S]),
    "qqbar_init": (None, [_P]), "qqbar_clear": (None, [_P]),
    "_qqbar_vec_init": (_P, [_S]), "_qqbar_vec_clear": (None, [_P, _S]),
    "qqbar_roots_fmpz_poly": (None, [_P, _P, _I]), "qqbar_equal": (_I, [_P, _P]),
    "qqbar_sgn_im": (_I, [_P]), "ca_get_qqbar": (_I, [_P, _P, _P]),
    "qqbar_degree": (_S, [_P]), "qqbar_get_acb": (None, [_P, _P, _S]),
    "fmpz_clear": (None, [_P]), "fmpz_set_str": (_I, [_P, _C, _I]),
    "fmpz_get_str": (_P, [_P, _I, _P]),
    "fmpq_clear": (None, [_P]),
    "fmpz_poly_init": (None, [_P]), "fmpz_poly_clear": (None, [_P]),
    "fmpz_poly_set_coeff_fmpz": (None, [_P, _S, _P]),
    "acb_init": (None, [_P]), "acb_clear": (None, [_P]),
    "arf_init": (None, [_P]), "arf_clear": (None, [_P]), "arf_set_mag": (None, [_P, _P]),
    "arf_get_fmpz_2exp": (None, [_P, _P, _P]), "arf_is_finite": (_I, [_P]), "mag_is_finite": (_I, [_P]),
    "flint_free": (None, [_P]),
}



# ---------------------------------------------------------------------------------------------
# the library and the context
# ---------------------------------------------------------------------------------------------

class Backend:
    """The loaded library, the one ``ca_ctx_t``, and the lock around every FLINT call."""

    __slots__ = ("lib", "path", "version", "ctx_buf", "ctx", "lock", "alive")

    def __init__(self, lib: ctypes.CDLL, path: Path, version: str):
        self.lib, self.path, self.version = lib, path, version
        self.lock = threading.RLock()
        self.ctx_buf = (c_ulong * (2 * STRUCT_SIZES["ca_ctx_struct"] // 8))(
            *([_SENTINEL] * (2 * STRUCT_SIZES["ca_ctx_struct"] // 8)))
        self.ctx = ctypes.addressof(self.ctx_buf)
        self.alive = False

    def close(self) -> None:
        with self.lock:
            if self.alive:
                self.alive = False
                self.lib.ca_ctx_clear(self.ctx)


_backend: Backend | None = None
_backend_error: str | None = None
_init_lock = threading.Lock()


def find_library() -> Path:
    """The libflint that python-flint loads (wheel: ``site-packages/python_flint.libs/``), else
    the system's libflint (a python-flint built against a shared FLINT)."""
    libdir = Path(flint.__file__).resolve().parent.parent / "python_flint.libs"
    found = sorted(libdir.glob("libflint*.so*"))
    if found:
        return found[0]
    import ctypes.util
    name = ctypes.util.find_library("flint")
    if name is None:
        raise OSError(f"no libflint*.so* in {libdir} and no system libflint")
    return Path(name)


def self_check(b: Backend) -> None:
    """Check the struct layouts against the library (raises RuntimeError on a mismatch)."""
    for name, size in STRUCT_SIZES.items():
        if ctypes.sizeof(CTYPES[name]) != size:
            raise RuntimeError(f"ctypes sizeof({name}) = {ctypes.sizeof(CTYPES[name])}, expected {size}")
    lib, n = b.lib, STRUCT_SIZES["ca_ctx_struct"] // 8
    # the context: ca_ctx_init writes exactly the first 120 bytes of a sentinel-filled buffer
    lib.ca_ctx_init(b.ctx)
    b.alive = True
    words = list(b.ctx_buf)
    if any(w != _SENTINEL for w in words[n:]):
        raise RuntimeError("ca_ctx_init wrote past sizeof(ca_ctx_struct) = 120")
    cx = _ca_ctx.from_address(b.ctx)
    if not (cx.field_qq and cx.field_qq_i and cx.mctx is None and cx.mctx_len == 0
            and cx.ext_cache.length >= 1 and cx.field_cache.length >= 2):
        raise RuntimeError("ca_ctx_struct fields are not where FLINT 3.6 puts them")
    for opt, default in ((_CA_OPT_PREC_LIMIT, 4096), (_CA_OPT_QQBAR_DEG_LIMIT, 120), (_CA_OPT_LOW_PREC, 64)):
        if cx.options[opt] != default or lib.ca_ctx_get_option(b.ctx, opt) != default:
            raise RuntimeError("ca_ctx_struct.options is not where FLINT 3.6 puts it")
    # a number: ca_init makes 0 in QQ (field = ctx->field_qq, num 0, den 1); ca_i puts i in QQ(i)
    m = CA_WORDS
    buf = (c_ulong * m)(*([_SENTINEL] * m))
    lib.ca_init(ctypes.addressof(buf), b.ctx)
    if list(buf[:3]) != [cx.field_qq, 0, 1] or any(w != _SENTINEL for w in buf[3:]):
        raise RuntimeError("ca_init does not write ca_struct as expected")
    lib.ca_i(ctypes.addressof(buf), b.ctx)
    ok = buf[0] == cx.field_qq_i and all(w == _SENTINEL for w in buf[STRUCT_SIZES["ca_struct"] // 8:])
    lib.ca_clear(ctypes.addressof(buf), b.ctx)
    if not ok:
        raise RuntimeError("ca_i does not write ca_struct as expected")
    # acb_init zeroes exp/size of each arf and exp/man of each mag; qqbar_init makes the
    # number 0 with minimal polynomial s (poly = {coeffs, alloc >= 2, length 2}) and acb_init
    acb_words = [0, 1, 4, 5, 6, 7, 10, 11]      # real.mid.exp/size, real.rad, imag.mid.exp/size, imag.rad
    for init, clear, size in (("qqbar_init", "qqbar_clear", 120), ("acb_init", "acb_clear", 96)):
        k = size // 8
        buf = (c_ulong * (2 * k))(*([_SENTINEL] * (2 * k)))
        getattr(lib, init)(ctypes.addressof(buf))
        w = list(buf)
        degree = lib.qqbar_degree(ctypes.addressof(buf)) if init == "qqbar_init" else None
        getattr(lib, clear)(ctypes.addressof(buf))
        if init == "qqbar_init":
            ok = w[0] not in (0, _SENTINEL) and 2 <= w[1] < _SENTINEL and w[2] == 2 and degree == 1
            ok = ok and all(w[3 + i] == 0 for i in acb_words)
        else:
            ok = all(w[i] == 0 for i in acb_words)
        if not ok or any(x != _SENTINEL for x in w[k:]):
            raise RuntimeError(f"{init} does not write {size} bytes as expected")


@contextlib.contextmanager
def qqbar_degree_limit(b: Backend, limit: int):
    """Calcium's degree limit of algebraic numbers (``CA_OPT_QQBAR_DEG_LIMIT``, 120 by default)
    set to ``limit`` inside the ``with`` block (the caller holds the lock), restored on exit."""
    old = b.lib.ca_ctx_get_option(b.ctx, _CA_OPT_QQBAR_DEG_LIMIT)
    b.lib.ca_ctx_set_option(b.ctx, _CA_OPT_QQBAR_DEG_LIMIT, limit)
    try:
        yield
    finally:
        b.lib.ca_ctx_set_option(b.ctx, _CA_OPT_QQBAR_DEG_LIMIT, old)


def backend() -> Backend:
    """The backend, loaded and checked on first call; raises RuntimeError when unavailable."""
    global _backend, _backend_error
    if _backend is not None:
        return _backend
    with _init_lock:
        if _backend is not None:
            return _backend
        if _backend_error is not None:
            raise RuntimeError(f"Calcium is not available: {_backend_error}")
        b = None
        try:
            if ctypes.sizeof(ctypes.c_long) != 8 or ctypes.sizeof(ctypes.c_void_p) != 8:
                raise OSError("the binding assumes a 64-bit LP64 platform")
            path = find_library()
            lib = ctypes.CDLL(str(path))        # the library python-flint has already loaded
            version = ctypes.cast(ctypes.addressof(ctypes.c_char.in_dll(lib, "flint_version")),
                                  ctypes.c_char_p).value.decode()
            major, minor = (int(p) for p in version.split(".")[:2])
            if major != 3 or minor < 3:
                raise OSError(f"FLINT {version}: the struct layouts are those of FLINT 3.3 to 3.6")
            for name, (restype, argtypes) in _SIGNATURES.items():
                fn = getattr(lib, name)         # AttributeError if a symbol is missing
                fn.restype, fn.argtypes = restype, argtypes
            b = Backend(lib, path, version)
            with b.lock:
                self_check(b)
        except Exception as exc:                # noqa: BLE001 -- any failure means "not available"
            _backend_error = f"{type(exc).__name__}: {exc}"
            if b is not None and b.alive:       # never clear (or use) a context whose layout we doubt
                b.alive = False
            raise RuntimeError(f"Calcium is not available: {_backend_error}") from exc
        atexit.register(b.close)
        _backend = b
        return b


@contextlib.contextmanager
def isolated_backend():
    """Within the block no backend is cached, so the next use loads (and checks) the library
    again, through :func:`find_library` as it is then; the previous backend (or load error) is
    restored on exit.  For tests of the loading path (a missing library, a bad layout)."""
    global _backend, _backend_error
    with _init_lock:
        saved = _backend, _backend_error
        _backend, _backend_error = None, None
    try:
        yield
    finally:
        with _init_lock:
            _backend, _backend_error = saved


def available() -> bool:
    """Whether Calcium can be used: library found, symbols present, struct layouts verified.

    Never raises.  The first call loads the library and creates the context.

    Examples
    --------
    >>> available()
    True
    """
    try:
        backend()
        return True
    except Exception:                           # noqa: BLE001
        return False


# ---------------------------------------------------------------------------------------------
# small helpers (call with the lock held)
# ---------------------------------------------------------------------------------------------

def truth(t: int) -> bool | None:
    return True if t == T_TRUE else False if t == T_FALSE else None


def take_str(lib: ctypes.CDLL, address: int | None) -> str:
    """Copy a FLINT-allocated C string into Python and free it with flint_free."""
    if not address:
        raise MemoryError("FLINT returned a NULL string")
    try:
        return ctypes.string_at(address).decode()
    finally:
        lib.flint_free(address)


def fmpz_to_int(lib: ctypes.CDLL, address: int) -> int:
    return int(take_str(lib, lib.fmpz_get_str(None, 16, address)), 16)


def _arf_to_python(lib: ctypes.CDLL, address: int) -> tuple[int, int]:
    """Exact (man, exp) with value man * 2^exp of a finite arf_t."""
    man, exp = _slong(0), _slong(0)
    try:
        lib.arf_get_fmpz_2exp(ctypes.byref(man), ctypes.byref(exp), address)
        return fmpz_to_int(lib, ctypes.addressof(man)), fmpz_to_int(lib, ctypes.addressof(exp))
    finally:
        lib.fmpz_clear(ctypes.byref(man))
        lib.fmpz_clear(ctypes.byref(exp))


def _arb_to_flint(lib: ctypes.CDLL, address: int) -> arb:
    """A python-flint arb containing the arb_t at ``address`` (exact midpoint, radius rounded up)."""
    mid_at, rad_at = address, address + ctypes.sizeof(_arf)
    if not (lib.arf_is_finite(mid_at) and lib.mag_is_finite(rad_at)):
        return arb(0, "inf")                    # [+/- inf]: still contains the value
    mid = arf(_arf_to_python(lib, mid_at))
    tmp = (c_ulong * (2 * ctypes.sizeof(_arf) // 8))()
    lib.arf_init(ctypes.addressof(tmp))
    try:
        lib.arf_set_mag(ctypes.addressof(tmp), rad_at)           # exact: a mag is a 30-bit float
        rad = arf(_arf_to_python(lib, ctypes.addressof(tmp)))
    finally:
        lib.arf_clear(ctypes.addressof(tmp))
    ball = arb(mid, rad)
    # python-flint keeps an arf midpoint exactly and rounds the radius up; check both anyway
    if not (ball.mid() == arb(mid) and ball.rad() >= arb(rad)):
        raise RuntimeError("python-flint did not transfer the ball exactly")
    return ball


def acb_from_address(lib: ctypes.CDLL, address: int) -> acb:
    return acb(_arb_to_flint(lib, address), _arb_to_flint(lib, address + ctypes.sizeof(_arb)))


class TempFmpz:
    """A temporary fmpz_t set from a Python int (cleared on exit of the ``with`` block)."""

    __slots__ = ("lib", "v")

    def __init__(self, lib: ctypes.CDLL, value: int):
        self.lib, self.v = lib, _slong(0)
        if lib.fmpz_set_str(ctypes.byref(self.v), format(int(value), "x").encode(), 16) != 0:
            lib.fmpz_clear(ctypes.byref(self.v))
            raise ValueError(f"fmpz_set_str failed on {value!r}")

    def __enter__(self) -> Any:
        return ctypes.byref(self.v)

    def __exit__(self, *exc: Any) -> None:
        self.lib.fmpz_clear(ctypes.byref(self.v))


# ---------------------------------------------------------------------------------------------
# algebraic numbers: the distinct roots of an integer polynomial, one of them by an enclosure
# ---------------------------------------------------------------------------------------------

PREC_LIMIT_ALGEBRAIC = 8192        # bits: root selection gives up above this


@contextlib.contextmanager
def qqbar_distinct_roots(lib: ctypes.CDLL, ints: list[int]):
    """The addresses of the distinct roots (qqbar_t) of the integer polynomial, valid inside the
    ``with`` block (caller holds the lock); cleared on exit."""
    deg = len(ints) - 1
    qsize = ctypes.sizeof(QqbarStruct)
    poly = (c_ulong * (2 * ctypes.sizeof(FmpzPolyStruct) // 8))()
    lib.fmpz_poly_init(ctypes.addressof(poly))
    vec = None
    try:
        for j, c in enumerate(ints):
            with TempFmpz(lib, c) as f:
                lib.fmpz_poly_set_coeff_fmpz(ctypes.addressof(poly), j, f)
        vec = lib._qqbar_vec_init(deg)
        lib.qqbar_roots_fmpz_poly(vec, ctypes.addressof(poly), 0)
        roots: list[int] = []
        for k in range(deg):
            at = vec + k * qsize
            if not 1 <= lib.qqbar_degree(at) <= deg:
                raise RuntimeError("qqbar_roots_fmpz_poly output does not have the expected layout")
            if not any(lib.qqbar_equal(at, r) for r in roots):
                roots.append(at)
        yield roots
    finally:
        if vec is not None:
            lib._qqbar_vec_clear(vec, deg)
        lib.fmpz_poly_clear(ctypes.addressof(poly))


def select_qqbar_root(lib: ctypes.CDLL, roots: list[int], target: acb, ball_mode: bool, approx: Any,
                 desc: str) -> int:
    """The address of the root singled out by ``target`` (caller holds the lock)."""
    buf = (c_ulong * (2 * ctypes.sizeof(AcbStruct) // 8))()
    at = ctypes.addressof(buf)
    prec = 64
    while True:
        encl = []
        lib.acb_init(at)
        try:
            for r in roots:
                lib.qqbar_get_acb(at, r, prec)
                encl.append(acb_from_address(lib, at))
        finally:
            lib.acb_clear(at)
        with flint.ctx.workprec(prec + 32):
            if ball_mode:
                meet = [k for k, e in enumerate(encl) if e.overlaps(target)]
                if not meet:
                    raise ValueError(f"no root of {desc} lies in approx {approx}")
                if len(meet) == 1:
                    return roots[meet[0]]
                failure = f"{len(meet)} roots may lie in it"
            else:
                mid = acb(target.real.mid(), target.imag.mid())
                dist = [abs(e - mid) for e in encl]
                best = min(range(len(roots)), key=lambda k: dist[k].mid())
                if all(dist[best] < dist[k] for k in range(len(roots)) if k != best):
                    return roots[best]
                failure = f"{sum(1 for d in dist if not dist[best] < d)} roots are as near"
        prec *= 2
        if prec > PREC_LIMIT_ALGEBRAIC:
            raise ValueError(f"approx {approx} does not single out one root of {desc} ({failure})")
