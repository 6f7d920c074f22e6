"""The layering of src/: the file-level import graph (`use crate::…`, `super::…`, paths in code;
re-exports and test modules left out), its cycles, and imports from a top-level module into one of
a higher layer. Prints both; exits 1 when there is either (`make lint` runs it).

    python3 scripts/layering.py [SRC_DIR]
"""
import os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else 'src'
files = {}
for d, _, fs in os.walk(root):
    for f in fs:
        if f.endswith('.rs'):
            p = os.path.join(d, f)
            rel = os.path.relpath(p, root)[:-3]
            parts = rel.split('/')
            if parts[-1] == 'mod': parts = parts[:-1]
            if parts == ['lib'] or parts == ['main']: parts = []
            files[tuple(parts)] = p
mods = set(files)
def strip_tests(s):
    # drop #[cfg(test)] mod tests { ... } blocks (brace-matched)
    out = []; i = 0
    for m in re.finditer(r'#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*mod\s+\w+\s*\{', s):
        if m.start() < i: continue
        out.append(s[i:m.start()]); depth = 0; j = m.end() - 1
        while j < len(s):
            if s[j] == '{': depth += 1
            elif s[j] == '}':
                depth -= 1
                if depth == 0: break
            j += 1
        i = j + 1
    out.append(s[i:]); return ''.join(out)
def resolve(path):
    # longest prefix that is a file module
    for k in range(len(path), 0, -1):
        if tuple(path[:k]) in mods: return tuple(path[:k])
    return None
def expand(prefix, body):
    # expand a use tree like a::{b, c::{d, e}} into paths (first segments only matter)
    body = body.strip()
    if not body.startswith('{'):
        return [prefix + [x for x in body.split('::') if x and x not in ('*',)]]
    inner = body[1:-1]; parts = []; depth = 0; cur = ''
    for ch in inner:
        if ch == '{': depth += 1
        if ch == '}': depth -= 1
        if ch == ',' and depth == 0: parts.append(cur); cur = ''
        else: cur += ch
    parts.append(cur); res = []
    for p in parts:
        p = p.strip().split(' as ')[0].strip()
        if not p: continue
        if p == 'self': res.append(prefix); continue
        m = re.match(r'([\w:]*?)(::)?(\{.*\})$', p, re.S)
        if m and m.group(3):
            res += expand(prefix + [x for x in m.group(1).split('::') if x], m.group(3))
        else:
            res.append(prefix + [x for x in p.split('::') if x and x != '*'])
    return res
edges = {}
test_only = lambda m: any(x.endswith('tests') or x == 'tests' for x in m)
for m, p in files.items():
    if test_only(m): continue
    s = strip_tests(open(p).read())
    s = re.sub(r'//[^\n]*', '', s)
    # re-exports are a module's facade, not a use: leave them out
    s = re.sub(r'\bpub(\([\w:]+\))?\s+use\s+[^;]*;', '', s, flags=re.S)
    is_dir_mod = p.endswith('mod.rs') or m == ()
    here = list(m) if is_dir_mod else list(m[:-1])  # module whose children `self::` names
    targets = set()
    for um in re.finditer(r'\buse\s+((?:crate|super|self)(?:::[\w]+)*)(::\{.*?\});|\buse\s+((?:crate|super|self)(?:::\w+)+);', s, re.S):
        if um.group(3): paths = [um.group(3).split('::')]
        else: paths = expand(um.group(1).split('::'), um.group(2)[2:])
        for path in paths:
            targets.add(tuple(path))
    for cm in re.finditer(r'(?<![\w:])(crate|super|self)((?:::\w+)+)', s):
        targets.add(tuple([cm.group(1)] + cm.group(2).split('::')[1:]))
    for path in targets:
        path = list(path)
        if path[0] == 'crate': abs_ = path[1:]
        elif path[0] == 'self': abs_ = list(m) + path[1:] if is_dir_mod else list(m) + path[1:]
        elif path[0] == 'super':
            base = list(m) if not is_dir_mod else list(m)
            base = base[:-1]
            rest = path[1:]
            while rest and rest[0] == 'super': base = base[:-1]; rest = rest[1:]
            abs_ = base + rest
        else: continue
        t = resolve(abs_)
        if t is None or t == m or test_only(t): continue
        # importing a parent module's re-export: count the edge to the parent file
        edges.setdefault(m, set()).add(t)
# Tarjan
idx = {}; low = {}; st = []; on = set(); sccs = []; c = [0]
sys.setrecursionlimit(10000)
def sc(v):
    idx[v] = low[v] = c[0]; c[0] += 1; st.append(v); on.add(v)
    for w in edges.get(v, ()):
        if w not in idx: sc(w); low[v] = min(low[v], low[w])
        elif w in on: low[v] = min(low[v], idx[w])
    if low[v] == idx[v]:
        comp = []
        while True:
            w = st.pop(); on.discard(w); comp.append(w)
            if w == v: break
        sccs.append(comp)
for v in list(files):
    if v not in idx and not test_only(v): sc(v)
cyc = [sorted('/'.join(x) or 'lib' for x in comp) for comp in sccs if len(comp) > 1]
print(f"files {len(files)}  edges {sum(len(v) for v in edges.values())}  cyclic SCCs {len(cyc)}")
for comp in sorted(cyc, key=len):
    print('  SCC', len(comp), ':', ' '.join(comp[:12]), '...' if len(comp) > 12 else '')
# layering between top-level modules
layers = [['cli','main'], ['bench','measure','render','sppm_render','render_settings','camera_sample','checkpoint','fingerprint','progress','denoise','adaptive'], ['integrator'], ['pbrt'], ['scene'],
          ['accel','light','material','media','bssrdf','film','filter','sensor','sensor_fit','settings'], ['texture','bsdf'],
          ['geometry','sampling','spectrum','image','io','camera'], ['simd','math','named']]
level = {n: i for i, l in enumerate(layers) for n in l}
unplaced = sorted({m[0] for m in files if m and m[0] not in level})
if unplaced: print('top-level modules in no layer:', ', '.join(unplaced))
up = []
for a, ts in edges.items():
    for b in ts:
        if not a or not b: continue
        la, lb = level.get(a[0]), level.get(b[0])
        if la is not None and lb is not None and lb < la:
            up.append(('/'.join(a), '/'.join(b)))
print(f"upward imports (file -> file in a higher layer): {len(up)}")
for a, b in sorted(up): print('  ', a, '->', b)
sys.exit(1 if cyc or up or unplaced else 0)
