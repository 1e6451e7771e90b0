"""Hostile arrays (issue 37): numpy broadcast and strided views whose
logical size dwarfs memory never abort the interpreter. Each call that
used to die with "memory allocation of ... failed" (SIGABRT, exit 134)
now raises MemoryError or ValueError with a clear message, or reads the
view in place and answers correctly.

Every hostile call runs in a child interpreter, so that a regression shows
as that test's failure (with the child's exit code and stderr) instead of
killing pytest. The children's timeout is a hang guard only, never a bound
on how fast anything runs.
"""

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import micromap_index as mmi

HANG_GUARD_S = 600


def overcommit_always():
    """Linux `vm.overcommit_memory = 1`: every reservation succeeds, so a
    multi-terabyte result is reserved and then filled, which is slow, not
    refused. The address space (2^47 bytes) still refuses exabytes."""
    try:
        return Path("/proc/sys/vm/overcommit_memory").read_text().strip() == "1"
    except OSError:
        return False


def run_child(code):
    """Runs `code` (which prints its verdict) in a fresh interpreter."""
    prelude = "import numpy as np, micromap_index as mmi\n"
    done = subprocess.run(
        [sys.executable, "-c", prelude + textwrap.dedent(code)],
        capture_output=True, text=True, timeout=HANG_GUARD_S,
    )
    assert done.returncode == 0, (
        f"the child exited {done.returncode} (-6 is SIGABRT):\n{done.stderr[-2000:]}"
    )
    return done.stdout.strip()


def raises(call, error):
    """A child's code: `call` must raise `error`; prints its message."""
    return f"""
    try:
        {call}
    except {error} as e:
        print("raised", e)
    else:
        print("returned")
    """


@pytest.mark.skipif(overcommit_always(), reason="vm.overcommit_memory = 1 reserves 4 TiB")
def test_the_issues_repro_is_a_memory_error():
    # The exact repro of issue 37: 2^40 float32 lanes, a 4 TiB result.
    out = run_child(raises(
        "b = np.broadcast_to(np.float32(.1), (2**40,)); mmi.index(b, b, 5)", "MemoryError"))
    assert out == ("raised the result: cannot allocate 4398046511104 bytes "
                   "(1099511627776 elements of 4 bytes)")


@pytest.mark.parametrize(
    "call, error, message",
    [
        # Results past the address space: refused whatever the overcommit policy.
        ("b = np.broadcast_to(np.float32(.1), (2**60,)); mmi.index(b, b, 5)",
         "MemoryError", "the result: cannot allocate 4611686018427387904 bytes"),
        ("b = np.broadcast_to(np.float32(.1), (2**60,)); mmi.wide_index(b, b, 20)",
         "MemoryError", "the result: cannot allocate 9223372036854775808 bytes"),
        ("b = np.broadcast_to(np.float32(.1), (2**30, 2**30)); mmi.index(b, b, 3)",
         "MemoryError", "the result: cannot allocate 4611686018427387904 bytes"),
        ("t = mmi.Tree.encode(np.zeros(16, np.uint8), 2)\n"
         "        t.lookup(np.broadcast_to(np.int64(3), (2**59,)))",
         "MemoryError", "lookup's result: cannot allocate 576460752303423488 bytes"),
        ("t = mmi.Tree.encode(np.zeros(16, np.uint8), 2)\n"
         "        t.lookup(np.broadcast_to(np.uint64(3), (2**59,)))",
         "MemoryError", "lookup's result: cannot allocate"),
        ("mmi.Tree.encode(np.broadcast_to(np.uint8(0), (2**60,)), 16)",
         "MemoryError", "states: cannot allocate 1152921504606846976 bytes"),
        # A texture of 2^40 texels: the library's dimension rule, before any copy.
        ("a = np.broadcast_to(np.uint8(255), (2**20, 2**20))\n"
         "        mmi.bake(a, np.zeros((1, 3, 2), np.float32), level=0)",
         "ValueError", "alpha: a 1048576x1048576 texture has 2^32 texels or more"),
        ("a = np.broadcast_to(np.float32(1), (2**20, 2**20))\n"
         "        mmi.verify(a, np.zeros((1, 3, 2), np.float32), data=b'', triangles=b'',"
         " indices=b'\\xff\\xff\\xff\\xff')",
         "ValueError", "alpha: a 1048576x1048576 texture has 2^32 texels or more"),
        # 2^40 triangles: their indices alone exceed max_bytes, refused uncopied.
        ("u = np.broadcast_to(np.float32(.5), (2**40, 3, 2))\n"
         "        mmi.bake(np.zeros((4, 4), np.uint8), u, level=0)",
         "ValueError", "uvs holds 1099511627776 triangles, whose indices alone take "
         "4398046511104 bytes, over the limit of max_bytes=1073741824 bytes"),
        # ... and with the limit raised, a copy past the address space.
        ("u = np.broadcast_to(np.float32(.5), (2**58, 3, 2))\n"
         "        mmi.bake(np.zeros((4, 4), np.uint8), u, level=0, max_bytes=2**62)",
         "MemoryError", "uvs: cannot allocate 6917529027641081856 bytes"),
        # verify: the buffers' index count is checked before uvs is copied.
        ("u = np.broadcast_to(np.float32(.5), (2**58, 3, 2))\n"
         "        mmi.verify(np.zeros((4, 4), np.uint8), u, data=b'', triangles=b'',"
         " indices=b'\\xff\\xff\\xff\\xff')",
         "ValueError", "the buffers have 1 indices for 288230376151711744 triangles"),
    ],
    ids=["index-2^60", "wide_index-2^60", "index-2^60-2d", "lookup-i64", "lookup-u64",
         "encode", "bake-alpha", "verify-alpha", "bake-uvs", "bake-uvs-raised", "verify-uvs"],
)
def test_hostile_arrays_raise(call, error, message):
    out = run_child(raises(call, error))
    assert out.startswith("raised " + message), out


def test_broadcast_and_strided_views_read_as_numpy_shows_them():
    """The in-place, chunked reading gives the contiguous arrays' answers
    (lengths that are not a multiple of the chunk, zero and negative
    strides, Fortran order)."""
    rng = np.random.default_rng(37)
    u = rng.random(10_007, dtype=np.float32) * np.float32(0.5)
    v = rng.random(10_007, dtype=np.float32) * np.float32(0.5)
    for uu, vv in [
        (np.broadcast_to(u[:1], (9_000,)), v[:9_000]),
        (u[::-1], v[::-1]),
        (u[::2], v[::2]),
        (np.asfortranarray(u[:10_000].reshape(100, 100)), v[:10_000].reshape(100, 100).T),
        (np.broadcast_to(u[:100], (100, 100)), np.broadcast_to(v[:100, None], (100, 100))),
    ]:
        want = mmi.index(np.ascontiguousarray(uu), np.ascontiguousarray(vv), 7)
        got = mmi.index(uu, vv, 7)
        assert got.shape == uu.shape and (got == want).all()
        assert (mmi.wide_index(uu, vv, 21) ==
                mmi.wide_index(np.ascontiguousarray(uu), np.ascontiguousarray(vv), 21)).all()
    tree = mmi.Tree.encode(rng.integers(0, 4, 4**5, dtype=np.uint8), 5)
    idx = np.broadcast_to(np.arange(4**5, dtype=np.int64)[::-3], (7, 342))
    assert (tree.lookup(idx) == tree.lookup(np.ascontiguousarray(idx))).all()
    states = np.broadcast_to(np.uint8(1), (4**6,))
    assert (mmi.Tree.encode(states, 6).decode() == 1).all()


def test_broadcast_inputs_bake_as_their_copies():
    """A broadcast texture (one row repeated) and broadcast UVs bake to the
    bytes of their contiguous copies."""
    row = (np.arange(64) % 7 > 2).astype(np.uint8) * np.uint8(255)
    alpha = np.broadcast_to(row, (64, 64))
    tri = np.array([[0, 0], [1, 0], [0, 1]], np.float32)
    uvs = np.broadcast_to(tri, (5, 3, 2))
    got = mmi.bake(alpha, uvs, level=3)
    want = mmi.bake(np.ascontiguousarray(alpha), np.ascontiguousarray(uvs), level=3)
    assert got.files() == want.files()
    assert mmi.verify(alpha, uvs, got).sound


def test_a_tiny_level_16_tree_decodes_or_raises_memory_error():
    # A tree whose root is a leaf is 26 bytes at any level; at level 16 it
    # decodes to 4^16 states (4 GiB). Under a 2 GiB address-space limit the
    # decode must raise MemoryError (it aborted the interpreter when the
    # library decoded infallibly). The address-space limit is 1 GiB above
    # what the child already maps (numpy imported), so only the 4 GiB fails.
    out = run_child("""
    import resource
    small = bytearray(mmi.Tree.encode(np.zeros(1, np.uint8), 0).to_bytes())
    assert small[6] == 0   # the level byte (bytes.rs: magic, version, layout, level)
    small[6] = 16
    tree = mmi.Tree.from_bytes(bytes(small))
    assert tree.level == 16
    mapped = next(int(line.split()[1]) * 1024 for line in open("/proc/self/status")
                  if line.startswith("VmSize:"))
    resource.setrlimit(resource.RLIMIT_AS, (mapped + (1 << 30), resource.RLIM_INFINITY))
    try:
        tree.decode()
    except MemoryError as e:
        print("raised", e)
    else:
        print("returned")
    """)
    assert out == "raised the states: cannot allocate 4294967296 bytes (4294967296 elements of 1 bytes)", out


def test_decode_fills_every_run():
    # The run-by-run decode against the encoder's input, both layouts.
    rng = np.random.default_rng(37)
    for level in range(0, 6):
        states = rng.integers(0, 4, 4**level).astype(np.uint8)
        states[: len(states) // 2] = 2  # a long run, so subtrees merge
        for layout in ("paper", "level-order"):
            tree = mmi.Tree.encode(states, level, layout=layout)
            assert np.array_equal(tree.decode(), states), (level, layout)
            back = mmi.Tree.from_bytes(tree.to_bytes())
            assert np.array_equal(back.decode(), states), (level, layout)
