# SPDX-License-Identifier: Apache-2.0
"""Trace decoding: every trace format codrive-dump reads, decoded by its library.

``for rec in codrive.dump.read("trace.log"):`` yields one dict per frame (and per note, such as
an SDO request left unanswered) with exactly the fields ``codrive-dump -r trace.log --json``
prints: ts, iface, id, ext, rtr, fd, len, data, service, node, severity, text.
"""
import json
import os
from typing import Dict, Iterator, List, Mapping, Optional, Union

from ._native import Error
from ._native import dump as _dump

PathLike = Union[str, "os.PathLike[str]"]


class Trace:
    """The decoded records of one file; iterate it once. Decoding runs on a C++ thread a few
    megabytes ahead of the loop, so a capture of any size streams in bounded memory."""

    def __init__(self, path: PathLike, eds: Optional[Mapping[int, PathLike]] = None,
                 profiles: Optional[Mapping[int, str]] = None, sdo_timeout: float = 1.0):
        eds_files = {int(node): os.fspath(p) for node, p in (eds or {}).items()}
        self._stream = _dump.TraceStream(os.fspath(path), eds_files, dict(profiles or {}),
                                         float(sdo_timeout))

    def __iter__(self) -> Iterator[Dict[str, object]]:
        rest = ""
        loads = json.loads
        while True:
            chunk = self._stream.next_chunk()
            if chunk is None:
                break
            lines = (rest + chunk).split("\n")
            rest = lines.pop()
            for line in lines:
                if line:
                    yield loads(line)
        if rest:
            yield loads(rest)
        if self._stream.fatal:
            raise Error("; ".join(self._stream.problems) or f"{self.path}: input ended early")

    @property
    def problems(self) -> List[str]:
        """Entries that could not be parsed and were skipped ("trace.log:12: ..."), why reading
        stopped early if it did (then iterating raises codrive.Error with them), and
        error findings of the EDS files given, so far."""
        return self._stream.problems

    @property
    def path(self) -> str:
        return self._stream.path


def read(path: PathLike, eds: Optional[Mapping[int, PathLike]] = None,
         profiles: Optional[Mapping[int, str]] = None, sdo_timeout: float = 1.0) -> Trace:
    """Decodes a trace in any format ``codrive-dump -r`` reads (candump log or screen text, PEAK
    .trc, Vector .asc and .blf, CSV, pcap/pcapng), each also gzip-compressed.

    eds: {node: "drive.eds"} for object names, types and default PDO mappings (``--eds``);
    profiles: {node: "akd2g"} to pin a drive profile (``--profile``); sdo_timeout: seconds after
    which an unanswered SDO request is reported. OSError if a file cannot be read."""
    return Trace(path, eds, profiles, sdo_timeout)


__all__ = ["Trace", "read"]
