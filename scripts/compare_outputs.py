#!/usr/bin/env python3
"""compare_outputs.py OLD NEW: compares two capture_outputs.sh directories: JSON with
timing keys masked, CSV with timing columns masked, text exactly; PNG and GIF are skipped."""
import sys, os, json, re
a, b = sys.argv[1], sys.argv[2]
TIMING = re.compile(r'(wall|time_s|_s$|_ms|elapsed|seconds)', re.I)
def norm_json(x):
    if isinstance(x, dict):
        return {k: ('<t>' if TIMING.search(k) else norm_json(v)) for k, v in x.items()}
    if isinstance(x, list): return [norm_json(v) for v in x]
    return x
diffs = 0
for root, _, files in os.walk(a):
    for f in files:
        pa = os.path.join(root, f); rel = os.path.relpath(pa, a); pb = os.path.join(b, rel)
        if f.endswith(('.png', '.gif')): continue
        if not os.path.exists(pb): print('MISSING', rel); diffs += 1; continue
        ta, tb = open(pa, errors='replace').read(), open(pb, errors='replace').read()
        if ta == tb: continue
        sa = '\n'.join(l for l in ta.splitlines() if not l.startswith('rc='))
        sb = '\n'.join(l for l in tb.splitlines() if not l.startswith('rc='))
        if ta.splitlines()[-1:] != tb.splitlines()[-1:]: print('RC', rel)
        try:
            ja, jb = json.loads(sa), json.loads(sb)
            if norm_json(ja) == norm_json(jb): continue
        except Exception:
            pass
        if f.endswith('.csv'):
            la, lb = ta.splitlines(), tb.splitlines()
            if la[:1] == lb[:1]:
                hdr = la[0].split(',')
                idx = [i for i, h in enumerate(hdr) if TIMING.search(h) or h in ('wall [ms]', 'solver ms')]
                strip = lambda ls: [[c for i, c in enumerate(l.split(',')) if i not in idx] for l in ls]
                if strip(la) == strip(lb): continue
        print('DIFF', rel); diffs += 1
for root, _, files in os.walk(b):
    for f in files:
        rel = os.path.relpath(os.path.join(root, f), b)
        if not os.path.exists(os.path.join(a, rel)): print('NEW', rel)
print('differences:', diffs)
