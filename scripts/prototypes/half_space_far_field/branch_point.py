import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from es import *
from closure import closure_sum, approx_far
ref=gl_sum(0.5,1e16,20)
ref2=gl_sum(0.5,1e15,16)
Ds=-np.logspace(-1,-11,41)
def row(s):
    errs=[]
    for D in Ds:
        e=approx_far(ref,1+D); a=approx_far(s,1+D)
        errs.append((a-e).real)
    return np.array(errs)
print("ref vs ref2 min", row(ref2).min())
print("current 1e10,8:", " ".join(f"{x:+.0e}" for x in row(gl_sum(1.0,1e10,8))[::4]))
for taumax in (1e3,1e6):
    print(f"GL horizon {taumax:.0e}:", " ".join(f"{x:+.0e}" for x in row(gl_sum(1.0,taumax,8))[::4]))
    for xcf in (1.0,0.1,0.01):
        print(f"closure {taumax:.0e} {xcf}:", " ".join(f"{x:+.0e}" for x in row(closure_sum(1.0,taumax,8,xcf))[::4]))
print("D:", " ".join(f"{x:.0e}" for x in Ds[::4]))
