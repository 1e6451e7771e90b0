"""A bake farm on Ray: many glTF assets baked as Ray tasks, one task per
asset, into a content-addressed cache (docs/python.md, "Bake farm").

    import ray
    from micromap_index import farm

    ray.init()                      # or ray.init(address="auto") on a cluster
    report = farm.bake_assets(["assets/"], "/shared/omm-cache", max_level=8)
    for r in report.results:
        print(r.status, r.asset, r.directory or r.error)

Each asset's cache key is the SHA-256 of the package version, the bake
options, the asset's bytes, the bytes of every file it names (buffers and
images, by their percent-decoded relative URIs) and, when the asset is
written back, the relative path from the cache to the asset (its URIs
point there). An asset whose key has an entry is not baked again.

An entry, ``CACHE/<key>/``, holds what ``micromap-index bake --gltf ASSET
--out CACHE/<key> --gltf-out asset.glb`` writes, byte for byte: the four
buffer files (:data:`micromap_index.FILE_NAMES`) and ``asset.glb`` (or
``asset.gltf`` with its sidecars), plus ``result.json`` (the bake's
statistics, meshes and warnings). An entry appears whole or not at all
(a task bakes into a temporary directory beside it and renames it). An
asset the library refuses (a ``ValueError``: malformed, over a limit)
gets an entry holding only ``error.json``, so it is not retried until it
changes; any other failure (a file that cannot be read, a worker that
died) is reported and retried on the next run. One asset's failure never
stops the others.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import struct
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union
from urllib.parse import unquote

import micromap_index as mmi

__all__ = [
    "AssetResult",
    "FarmReport",
    "bake_assets",
    "cache_key",
    "find_assets",
    "referenced_files",
]

#: Bumped when an entry's layout or the key's recipe changes.
CACHE_FORMAT = "micromap-index farm 1"

_PathLike = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class AssetResult:
    """One asset's outcome. ``status``: ``"baked"`` (by this run),
    ``"cached"`` (an entry was there) or ``"failed"``; ``directory``: the
    cache entry with the outputs (``None`` when failed); ``error``: the
    failure's message; ``cached_failure``: the failure was read from the
    cache (the library refused this exact asset before)."""

    asset: str
    status: str
    key: str
    directory: Optional[str] = None
    error: Optional[str] = None
    cached_failure: bool = False


@dataclass
class FarmReport:
    """What :func:`bake_assets` did: one :class:`AssetResult` per asset in
    the order given, and the counts. ``tasks`` is the number of Ray tasks
    submitted (0 when everything was cached)."""

    results: List[AssetResult] = field(default_factory=list)
    tasks: int = 0

    @property
    def baked(self) -> int:
        return sum(r.status == "baked" for r in self.results)

    @property
    def cached(self) -> int:
        return sum(r.status == "cached" for r in self.results)

    @property
    def failed(self) -> int:
        return sum(r.status == "failed" for r in self.results)


def find_assets(paths: Iterable[_PathLike]) -> List[Path]:
    """The glTF assets in ``paths``: a file as given, a folder searched
    recursively for ``*.gltf`` and ``*.glb`` (sorted, so runs are
    repeatable). A path that does not exist is an ``OSError``."""
    found: List[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            found.extend(sorted(q for q in p.rglob("*") if q.suffix.lower() in (".gltf", ".glb")
                                and q.is_file()))
        elif p.exists():
            found.append(p)
        else:
            raise FileNotFoundError(f"{p}: no such file or folder")
    return found


def _gltf_json(data: bytes) -> Optional[dict]:
    """The JSON of a ``.gltf`` or of a ``.glb``'s first chunk, or ``None``
    when it does not parse (the bake then reports why)."""
    try:
        if data[:4] == b"glTF":
            length, kind = struct.unpack_from("<II", data, 12)
            if kind != 0x4E4F534A:  # "JSON"
                return None
            data = data[20:20 + length]
        value = json.loads(data.decode("utf-8-sig"))
        return value if isinstance(value, dict) else None
    except (ValueError, struct.error, UnicodeDecodeError):
        return None


def referenced_files(asset: _PathLike) -> List[str]:
    """The relative URIs (percent-decoded) of the buffers and images
    ``asset`` names, sorted; ``data:`` URIs are inside the asset's own
    bytes and are not listed."""
    doc = _gltf_json(Path(asset).read_bytes())
    if doc is None:
        return []
    uris = set()
    for kind in ("buffers", "images"):
        items = doc.get(kind)
        for item in items if isinstance(items, list) else []:
            uri = item.get("uri") if isinstance(item, dict) else None
            if isinstance(uri, str) and not uri.startswith("data:"):
                uris.add(unquote(uri))
    return sorted(uris)


def _file_digest(path: Path) -> str:
    h = hashlib.sha256()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError as e:
        return f"unreadable: {type(e).__name__}"
    return h.hexdigest()


def _uri_base(asset: Path, cache_dir: Path) -> str:
    """How an entry (``cache_dir/<key>``) reaches the asset's folder (part
    of the key: a written glTF stands alone, but an entry stays tied to the
    cache it was baked for)."""
    return os.path.relpath(asset.resolve().parent, cache_dir.resolve() / "entry")


def cache_key(asset: _PathLike, options: Dict[str, Any], cache_dir: Optional[_PathLike] = None,
              gltf_out: Optional[str] = "glb") -> str:
    """The content address of baking ``asset`` with ``options``
    (:func:`micromap_index.bake_gltf`'s keywords) into ``cache_dir``: a hex
    SHA-256 over the package version, the options, the asset's bytes, each
    referenced file's name and bytes, and (with ``gltf_out``) the path from
    the cache to the asset."""
    asset = Path(asset)
    header = {
        "format": CACHE_FORMAT,
        "version": mmi.__version__,
        # The bytes are the same on every thread count.
        "options": {k: v for k, v in options.items() if k != "threads"},
        "gltf_out": gltf_out,
    }
    if gltf_out is not None:
        if cache_dir is None:
            raise TypeError("cache_key needs cache_dir when the asset is written back")
        header["uri_base"] = _uri_base(asset, Path(cache_dir))
    h = hashlib.sha256()
    h.update(json.dumps(header, sort_keys=True, default=str).encode())
    h.update(b"\0asset\0" + _file_digest(asset).encode())
    for uri in referenced_files(asset):
        h.update(b"\0file\0" + uri.encode() + b"\0" + _file_digest(asset.parent / uri).encode())
    return h.hexdigest()


def _entry_state(entry: Path) -> Optional[AssetResult]:
    """What an existing entry says (``asset`` and ``key`` left blank)."""
    if (entry / "result.json").is_file():
        return AssetResult(asset="", status="cached", key="", directory=str(entry))
    error = entry / "error.json"
    if error.is_file():
        message = json.loads(error.read_text()).get("error", "")
        return AssetResult(asset="", status="failed", key="", error=message,
                           cached_failure=True)
    return None


def _publish(temporary: str, entry: str) -> None:
    """Renames the finished ``temporary`` to ``entry``; if another task got
    there first, its entry stays and ``temporary`` is removed."""
    try:
        os.rename(temporary, entry)
    except OSError:
        if not os.path.isdir(entry):
            raise
        shutil.rmtree(temporary, ignore_errors=True)


def bake_one(asset: str, key: str, cache_dir: str, options: Dict[str, Any],
             gltf_out: Optional[str]) -> Dict[str, Any]:
    """Bakes one asset into ``cache_dir/<key>`` (the body of a Ray task;
    callable without Ray). Returns ``{"status": ..., "error": ...}``."""
    entry = os.path.join(cache_dir, key)
    state = _entry_state(Path(entry))
    if state is not None:  # another task baked it meanwhile
        return {"status": state.status, "error": state.error}
    # Beside the entry: the written glTF's URIs are the entry's.
    temporary = tempfile.mkdtemp(prefix=f".{key}.", dir=cache_dir)
    try:
        try:
            result = mmi.bake_gltf(
                asset,
                gltf_out=None if gltf_out is None else os.path.join(temporary, f"asset.{gltf_out}"),
                **options,
            )
        except ValueError as e:
            # The library refuses these bytes: remembered, not retried.
            with open(os.path.join(temporary, "error.json"), "w") as f:
                json.dump({"asset": asset, "error": str(e)}, f, indent=2)
            _publish(temporary, entry)
            return {"status": "failed", "error": str(e)}
        for name, content in result.files().items():
            with open(os.path.join(temporary, name), "wb") as f:
                f.write(content)
        summary = {"asset": asset, "options": options, "stats": result.stats,
                   "meshes": result.meshes, "warnings": result.warnings}
        with open(os.path.join(temporary, "result.json"), "w") as f:
            json.dump(summary, f, indent=2, default=str)
        _publish(temporary, entry)
        return {"status": "baked"}
    except Exception as e:  # reported per asset; the farm goes on
        shutil.rmtree(temporary, ignore_errors=True)
        return {"status": "failed", "error": f"{type(e).__name__}: {e}"}


def print_progress(done: int, total: int, result: AssetResult) -> None:
    """The default progress: one line per finished asset on stderr."""
    detail = result.directory if result.status != "failed" else result.error
    print(f"[{done}/{total}] {result.status} {result.asset}: {detail}", file=sys.stderr,
          flush=True)


def bake_assets(
    assets: Union[_PathLike, Sequence[_PathLike]],
    cache_dir: _PathLike,
    *,
    gltf_out: Optional[str] = "glb",
    cpus_per_task: int = 1,
    memory_per_task: Optional[int] = None,
    progress: Optional[Callable[[int, int, AssetResult], None]] = print_progress,
    **options: Any,
) -> FarmReport:
    """Bakes every glTF asset of ``assets`` (files or folders, see
    :func:`find_assets`) with :func:`micromap_index.bake_gltf`'s
    ``options``, one Ray task per asset not yet in ``cache_dir``.

    ``gltf_out``: ``"glb"`` (default) or ``"gltf"`` writes each asset back
    with its micromaps as ``asset.glb`` / ``asset.gltf`` in its entry;
    ``None`` writes the buffer files only. ``cpus_per_task`` is each
    task's Ray ``num_cpus`` and its bake's ``threads``; ``memory_per_task``
    (bytes) its Ray ``memory`` reservation, so that Ray does not start
    more bakes on a node than fit. ``progress(done, total, result)`` is
    called as each asset finishes (cached ones first).

    Uses the running Ray (``ray.init()`` first to choose a cluster); starts
    a local one when none is running. Returns a :class:`FarmReport`;
    failures are in it, never raised (except for a ``cache_dir`` that
    cannot be made or an asset path that does not exist)."""
    import ray  # the farm's only use of Ray: the package works without it

    if isinstance(assets, (str, os.PathLike)):
        assets = [assets]
    if gltf_out not in (None, "glb", "gltf"):
        raise ValueError(f'gltf_out {gltf_out!r}: expected "glb", "gltf" or None')
    if "threads" in options or "gltf_out" in options:
        raise TypeError("threads come from cpus_per_task, and gltf_out names a container")
    options = {**options, "threads": cpus_per_task}
    cache = Path(cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    cache = cache.resolve()
    paths = [str(p.resolve()) for p in find_assets(assets)]
    keys = [cache_key(p, options, cache, gltf_out) for p in paths]
    results: List[Optional[AssetResult]] = [None] * len(paths)
    total, done = len(paths), 0
    report = FarmReport()

    def finish(i: int, result: AssetResult) -> None:
        nonlocal done
        results[i] = result
        done += 1
        if progress is not None:
            progress(done, total, result)

    task = None  # bake_one as a Ray remote function, made once, only if needed
    pending: Dict[Any, int] = {}
    submitted: Dict[str, Any] = {}  # one task per key, however often the asset is listed
    waiting: Dict[str, List[int]] = {}
    for i, (path, key) in enumerate(zip(paths, keys)):
        state = _entry_state(cache / key)
        if state is not None:
            finish(i, AssetResult(path, state.status, key, state.directory, state.error,
                                  state.cached_failure))
            continue
        if key in submitted:
            waiting[key].append(i)
            continue
        if task is None:
            if not ray.is_initialized():
                ray.init()
            task = ray.remote(bake_one)
        ref = task.options(
            num_cpus=cpus_per_task, memory=memory_per_task, max_retries=0,
            name=f"bake {Path(path).name}",
        ).remote(path, key, str(cache), options, gltf_out)
        submitted[key] = ref
        waiting[key] = [i]
        pending[ref] = i
        report.tasks += 1
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        i = pending.pop(ready[0])
        key = keys[i]
        try:
            outcome = ray.get(ready[0])
        except Exception as e:  # a worker that died: that asset only
            outcome = {"status": "failed", "error": f"{type(e).__name__}: {e}"}
        entry = cache / key
        for j in waiting.pop(key):
            status = outcome["status"]
            finish(j, AssetResult(
                paths[j], status, key,
                directory=str(entry) if status != "failed" else None,
                error=outcome.get("error"),
            ))
    report.results = [r for r in results if r is not None]
    return report


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m micromap_index.farm ASSET_OR_FOLDER... --cache DIR
    [--max-level N] [--level L] [--mips M] [--gltf-out glb|gltf|none]
    [--cpus-per-task N] [--address RAY_ADDRESS]``: exit 0 when every asset
    baked or was cached, 1 when any failed."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m micromap_index.farm",
                                     description="Bake glTF assets on Ray into a cache.")
    parser.add_argument("assets", nargs="+")
    parser.add_argument("--cache", required=True)
    parser.add_argument("--level", default="auto")
    parser.add_argument("--max-level", type=int, default=12)
    parser.add_argument("--mips", default="0")
    parser.add_argument("--gltf-out", default="glb", choices=["glb", "gltf", "none"])
    parser.add_argument("--cpus-per-task", type=int, default=1)
    parser.add_argument("--address", default=None,
                        help="a Ray cluster (ray.init's address); default: a local one")
    args = parser.parse_args(argv)
    import ray

    ray.init(address=args.address)
    level = args.level if args.level == "auto" else int(args.level)
    mips = args.mips if args.mips == "all" else int(args.mips)
    started = time.monotonic()
    report = bake_assets(args.assets, args.cache, max_level=args.max_level, level=level,
                         mips=mips, gltf_out=None if args.gltf_out == "none" else args.gltf_out,
                         cpus_per_task=args.cpus_per_task)
    print(f"{report.baked} baked, {report.cached} cached, {report.failed} failed "
          f"({report.tasks} tasks, {time.monotonic() - started:.1f} s)", file=sys.stderr)
    return 1 if report.failed else 0


if __name__ == "__main__":
    sys.exit(main())
