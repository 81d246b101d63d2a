import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from es import *
from scipy.integrate import quad
def exact_far(shear,omega,tau0=1.0):
    b=1.0 if shear else 1/r
    D=omega-b
    def f(u,part):
        x=u*u
        v=2*u*density(shear,x)*np.exp(-x*tau0-1j*D*tau0)/(x+1j*D)
        return v.real if part==0 else v.imag
    pts=[np.sqrt(abs(D))] if D!=0 else None
    re=quad(f,0,10,args=(0,),points=pts,limit=2000,epsabs=1e-14,epsrel=1e-12)[0]
    im=quad(f,0,10,args=(1,),points=pts,limit=2000,epsabs=1e-14,epsrel=1e-12)[0]
    return re+1j*im
def approx_far(sums,omega,tau0=1.0):
    tot=0
    for shear,(x,w) in zip((True,False),sums):
        b=1.0 if shear else 1/r
        D=omega-b
        tot+=np.sum(w*np.exp(-x*tau0-1j*D*tau0)/(x+1j*D))
    return tot
if __name__=="__main__":
    for taumax in (1e3,1e6,1e10):
        s=gl_sum(1.0,taumax,8)
        out=[]
        for D in (-0.3,-1e-2,-1e-3,-1e-4,-1e-5,-1e-6,-1e-7,-1e-8,-1e-10,1e-8,1e-6,1e-4,1e-2):
            om=1+D
            e=exact_far(True,om)+exact_far(False,om)
            a=approx_far(s,om)
            out.append(f"{D:.0e}:{(a-e).real:+.1e}")
        print(f"{taumax:.0e}", " ".join(out))
