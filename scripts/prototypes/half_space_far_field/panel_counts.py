import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from es import *
ref=gl_sum(0.5,1e14,16)
for taumax in (1e3,1e6,1e10):
    tau=np.concatenate([np.linspace(1,50,2000),np.logspace(1.7,np.log10(taumax),3000)])
    R=[envelope(b,tau) for b in ref]
    for npp,ratio in ((8,2),(6,2),(10,3),(12,4),(8,3),(14,6),(16,8)):
        s=gl_sum(1.0,taumax,npp,ratio)
        err=sum(np.abs(envelope(b,tau)-Rb) for b,Rb in zip(s,R))
        print(f"taumax {taumax:.0e} npp {npp} ratio {ratio}: n={sum(len(b[0]) for b in s)} maxerr {err.max():.2e}")
