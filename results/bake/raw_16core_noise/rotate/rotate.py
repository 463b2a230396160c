#!/usr/bin/python3
"""Issue 19: per iteration, the slowest ranks of each run in rotate/ (every rank moved from core r
to core (r + 8) % 16 during iteration 3) and still/ (left); whether iteration 5 follows the
process (corr with its own iteration 2) or the core (corr with the iteration 2 of the rank that
had its new core). Usage: rotate.py DIR (DIR holds runs/)."""
import json,h5py,glob,numpy as np,sys
np.set_printoptions(precision=3,suppress=True,linewidth=220)
for j in sorted(glob.glob(sys.argv[1]+'/runs/*.json')):
    f=h5py.File(j[:-5]+'.h5'); t=f['iterations/trace_time'][:]
    ph=f['phases/names'][:]; st=f['phases/start'][:]; en=f['phases/end'][:]
    name=j.split('/')[-1][:-5]
    rel=t[:,1:]/t[:,1:].mean(axis=0)
    print(name, 'iteration means', t.mean(axis=0).round(3))
    for k in range(rel.shape[1]): print('  it%d slowest %s  x%.3f'%(k+1, np.argsort(-rel[:,k])[:3], rel[:,k].max()))
    # correlation between iterations 2 and 5/6
    print('  corr(it2,it5) %.2f corr(it2,it6) %.2f corr(it5,it6) %.2f'%(np.corrcoef(rel[:,1],rel[:,4])[0,1],np.corrcoef(rel[:,1],rel[:,5])[0,1],np.corrcoef(rel[:,4],rel[:,5])[0,1]))
    # core-following hypothesis: rank r's it5 vs rank (r-8)'s it2 (the rank that was on r's new core)
    shifted=np.roll(rel[:,1],8)  # shifted[r]=rel[(r-8)%16, it2]
    print('  corr(it5 of rank r, it2 of the rank that had its new core) %.2f'%np.corrcoef(rel[:,4],shifted)[0,1])
    i=list(ph).index(b'iterate'); print('  iterate start (rank0) %.3f end %.3f'%(st[0,i],en[0,i]))
