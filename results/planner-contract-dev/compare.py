import json, sys, math
def load(*ps):
    out={}
    for p in ps:
        try:
            for l in open(p):
                r=json.loads(l); out[(r['task'],r['method'],r['index'])]=r
        except FileNotFoundError: pass
    return out
import os
here=os.path.dirname(os.path.abspath(__file__))
b=load(os.path.join(here,'base-t1','trials.jsonl')); a=load(*sys.argv[1:])
sv=lambda r: sum(r['simulated'].values()) if isinstance(r.get('simulated'),dict) else r.get('simulated')
rows=[]
for k in sorted(a):
    rb=b.get(k); ra=a[k]
    print(k, 'base', rb and (rb['status'][0], round(rb['time_s'],1), sv(rb), rb['skeletons']), 'after', (ra['status'][0], round(ra['time_s'],1), sv(ra), ra['skeletons']))
    if rb: rows.append((sv(rb), sv(ra), rb['time_s'], ra['time_s']))
if rows:
    g=lambda xs: math.exp(sum(math.log(max(x,1e-9)) for x in xs)/len(xs))
    print("n",len(rows),"gm values base/after", round(g([r[0] for r in rows]),1), round(g([r[1] for r in rows]),1), "gm time", round(g([r[2] for r in rows]),2), round(g([r[3] for r in rows]),2))
