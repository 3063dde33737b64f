#!/usr/bin/env python3
"""Regenerates the vendored Kubernetes batch/v1 Job schema that tests/sweep_k8s.rs checks the
manifest of `shoal sweep --engine k8s` against:

    crates/shoal-cli/tests/k8s-schema/job-batch-v1.json

From the PyPI package kubernetes-validate (Apache-2.0), which ships the JSON schemas of each
Kubernetes version converted from its OpenAPI definitions; the "local-strict" set forbids
fields the API does not have (additionalProperties: false). Its Job schema refers to
`/api/_definitions.json#/$defs/...`; this script copies the Job schema and every definition
it reaches, directly or through others, into one standalone file whose references are
`#/$defs/...`, so a validator needs no file or network access.

Usage: scripts/vendor-k8s-schema.py [package-version [kubernetes-version]]
(default 1.37.0 and v1.37.0). Needs pip and PyPI; cargo and CI never do: the file is
committed. Idempotent: the same inputs give the same file.
"""

import json
import pathlib
import subprocess
import sys
import tempfile
import zipfile

PACKAGE = sys.argv[1] if len(sys.argv) > 1 else "1.37.0"
KUBERNETES = sys.argv[2] if len(sys.argv) > 2 else "v1.37.0"
ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "crates/shoal-cli/tests/k8s-schema/job-batch-v1.json"
PREFIX = "/api/_definitions.json#/$defs/"
INNER = "#/$defs/"  # how the definitions refer to each other


def name_of(ref):
    """The definition a reference names."""
    for p in (PREFIX, INNER):
        if ref.startswith(p):
            return ref[len(p):]
    raise SystemExit(f"unexpected reference {ref}")


def refs(node):
    """Every $ref string below `node`."""
    if isinstance(node, dict):
        for k, v in node.items():
            if k == "$ref" and isinstance(v, str):
                yield v
            else:
                yield from refs(v)
    elif isinstance(node, list):
        for v in node:
            yield from refs(v)


def local(node):
    """`node` with its references pointing into its own $defs."""
    if isinstance(node, dict):
        return {
            k: (INNER + name_of(v) if k == "$ref" else local(v))
            for k, v in node.items()
        }
    if isinstance(node, list):
        return [local(v) for v in node]
    return node


def main():
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run(
            [sys.executable, "-m", "pip", "download", "--no-deps", "--quiet", "-d", tmp,
             f"kubernetes-validate=={PACKAGE}"],
            check=True,
        )
        wheel = next(pathlib.Path(tmp).glob("kubernetes_validate-*.whl"))
        base = f"kubernetes_validate/kubernetes-json-schema/{KUBERNETES}-local-strict/"
        with zipfile.ZipFile(wheel) as z:
            job = json.loads(z.read(base + "job-batch-v1.json"))
            defs = json.loads(z.read(base + "_definitions.json"))["$defs"]
    wanted, todo = set(), list(refs(job))
    while todo:
        name = name_of(todo.pop())
        if name not in wanted:
            wanted.add(name)
            todo.extend(refs(defs[name]))
    schema = local(job)
    schema.pop("$id", None)
    schema["$comment"] = (
        f"Kubernetes {KUBERNETES} batch/v1 Job, strict; from the PyPI package "
        f"kubernetes-validate {PACKAGE} ({base}job-batch-v1.json and the definitions it "
        "reaches in _definitions.json), made standalone by scripts/vendor-k8s-schema.py"
    )
    schema["$defs"] = {name: local(defs[name]) for name in sorted(wanted)}
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(schema, indent=1, sort_keys=True) + "\n")
    print(f"{OUT.relative_to(ROOT)}: the Job and {len(wanted)} definitions")


main()
