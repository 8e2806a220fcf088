"""The resumable sweeps' checkpoint file (JSON lines), one rule for the clogging and the hopper sweeps:
the first line is the sweep's parameters (its signature), then one finished record per line, each
flushed and fsynced as it is written, so an interrupted sweep loses no finished record. Reopened
with the same signature it hands back the records it holds (an empty or torn last line, from a kill
while writing, is skipped); another signature raises ValueError naming what differs."""
import json
import os


class Checkpoint:
    """Checkpoint(path, signature): `records` holds what the file already has; append(record) adds one.
    path None keeps nothing."""

    def __init__(self, path, signature):
        self.records, self._out = [], None
        if path is None:
            return
        if os.path.exists(path):
            with open(path) as f:
                lines = f.read().split("\n")
            header = json.loads(lines[0])
            if header != signature:
                changed = sorted(k for k in set(header) | set(signature) if header.get(k) != signature.get(k))
                raise ValueError("checkpoint %s holds another sweep (differs in %s)" % (path, ", ".join(changed)))
            for line in lines[1:]:
                try:
                    self.records.append(json.loads(line))
                except ValueError:  # an empty or torn last line (killed while writing)
                    continue
        else:
            with open(path, "w") as f:
                f.write(json.dumps(signature) + "\n")
                f.flush()
                os.fsync(f.fileno())
        self._out = open(path, "a")

    def append(self, record):
        if self._out is not None:
            self._out.write(json.dumps(record) + "\n")
            self._out.flush()
            os.fsync(self._out.fileno())

    def close(self):
        if self._out is not None:
            self._out.close()
            self._out = None


def run_indexed(count, run_one, checkpoint, signature, unit, progress=False, on_record=None):
    """The loop of a sweep of `count` independent runs, one record each (the hopper's widths, the
    capsule's (η, Ca) points): run_one(k) returns run k's record (a JSON-able dict); records the
    checkpoint already holds are reused, each new one is appended at once (with its "index") and
    handed to on_record(k, record). Returns the records in index order."""
    ck = Checkpoint(checkpoint, signature)
    done = {r["index"]: r for r in ck.records}
    todo = [k for k in range(count) if k not in done]
    from .droplets import _progress_bar
    bar = _progress_bar(len(todo), unit, progress and bool(todo))
    try:
        for k in todo:
            record = dict(run_one(k), index=k)
            done[k] = record
            ck.append(record)
            if bar is not None:
                bar.update(1)
            if on_record is not None:
                on_record(k, record)
    finally:
        ck.close()
        if bar is not None:
            bar.close()
    return [done[k] for k in range(count)]
