#!/bin/bash
# count.sh P BVH [extra bake args]: nodes per mirror ray on rooms_P.bs
p=$1; b=$2; shift 2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false OMP_NUM_THREADS=1
tag=${TAG:-}
nice mpirun -n 2 --oversubscribe --bind-to none ${BAKE:-build/miniapps/bake/bake} rooms_$p.bs -o o_$p$b$tag.bsb --viewpoints 20 --iterations 1 --bvh $b --summary s_$p$b$tag.json "$@" > s_$p$b$tag.log 2>&1
python3 -c "
import json,sys;d=json.load(open('s_$p$b$tag.json'));w=d['scene']['work']
print('$p $b$tag', round(sum(w['trace_nodes']['per_rank'])/sum(w['trace_rays']['per_rank']),3), d['verification_hash'] if 'verification_hash' in d else '')"
grep verification s_$p$b$tag.log | tail -1
