"""Side by side, per cell (task, method) and per method: solved counts, geometric means of
time and of values simulated. `python compare.py BASE/trials.jsonl AFTER/trials.jsonl`"""
import json, sys, math, collections
def load(p):
    out={}
    for l in open(p):
        r=json.loads(l); out[(r['task'],r['method'],r['index'])]=r
    return out
b=load(sys.argv[1]); a=load(sys.argv[2])
sv=lambda r: sum(r['simulated'].values()) if isinstance(r.get('simulated'),dict) else (r.get('simulated') or 0)
g=lambda xs: math.exp(sum(math.log(max(x,1e-9)) for x in xs)/len(xs)) if xs else float('nan')
cells=collections.defaultdict(list)
for k in sorted(a):
    if k in b: cells[k[:2]].append((b[k],a[k]))
tot=[]
for c,rows in sorted(cells.items()):
    sb=sum(r[0]['status']=='solved' for r in rows); sa=sum(r[1]['status']=='solved' for r in rows)
    both=[r for r in rows if r[0]['status']=='solved' and r[1]['status']=='solved']
    tot+=rows
    print(f"{c[0]:15s} {c[1]:15s} solved {sb}/{len(rows)} -> {sa}/{len(rows)}  gm time {g([r[0]['time_s'] for r in rows]):6.2f} -> {g([r[1]['time_s'] for r in rows]):6.2f}   gm values {g([max(sv(r[0]),1) for r in rows]):7.1f} -> {g([max(sv(r[1]),1) for r in rows]):7.1f}")
for m in sorted({k[1] for k in cells}):
    rows=[r for c,rs in cells.items() if c[1]==m for r in rs]
    print('ALL', m, 'solved', sum(r[0]['status']=='solved' for r in rows), '->', sum(r[1]['status']=='solved' for r in rows), '/', len(rows), 'gm time %.2f -> %.2f'%(g([r[0]['time_s'] for r in rows]), g([r[1]['time_s'] for r in rows])), 'gm values %.1f -> %.1f'%(g([max(sv(r[0]),1) for r in rows]), g([max(sv(r[1]),1) for r in rows])))
