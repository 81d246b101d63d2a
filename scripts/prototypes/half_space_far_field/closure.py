import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from es import *
from freq import exact_far
from scipy.integrate import quad
def closure_sum(tau_min,tau_max,npp,xc_factor,ratio=2.0):
    # panels in u from u_c=sqrt(xc) (xc = xc_factor/tau_max) doubling to u_max; [0,u_c] lumped in one node at first moment
    u_c=np.sqrt(xc_factor/tau_max); u_max=np.sqrt(36/tau_min)
    e=[u_c]
    while e[-1]<u_max: e.append(ratio*e[-1])
    xg,wg=np.polynomial.legendre.leggauss(npp)
    xgl,wgl=np.polynomial.legendre.leggauss(12)
    out=[]
    for shear in (True,False):
        xs=[];ws=[]
        # lump: W0 = int_0^uc 2u rho(u^2) du, x0 = int x*.../W0 (complex ratio -> take real part of mean)
        u=0.5*u_c*(xgl+1); w=0.5*u_c*wgl
        f=w*2*u*density(shear,u*u)
        W0=f.sum(); m1=(f*u*u).sum()
        x0=(m1/W0).real
        xs.append(np.array([x0])); ws.append(np.array([W0]))
        for a,c in zip(e[:-1],e[1:]):
            u=0.5*(c-a)*xg+0.5*(c+a); w=0.5*(c-a)*wg
            xs.append(u*u); ws.append(w*2*u*density(shear,u*u))
        out.append((np.concatenate(xs),np.concatenate(ws)))
    return out
def approx_far(sums,omega,tau0=1.0):
    tot=0
    for shear,(x,w) in zip((True,False),sums):
        b=1.0 if shear else 1/r
        D=omega-b
        tot+=np.sum(w*np.exp(-x*tau0-1j*D*tau0)/(x+1j*D))
    return tot
if __name__=="__main__":
    ref=gl_sum(0.5,1e14,16)
    for taumax in (1e3,1e6):
      for xcf in (1.0,0.1,0.01):
        s=closure_sum(1.0,taumax,8,xcf)
        tau=np.concatenate([np.linspace(1,50,2000),np.logspace(1.7,np.log10(taumax),3000)])
        err=sum(np.abs(envelope(b,tau)-envelope(rb,tau)) for b,rb in zip(s,ref))
        out=[]
        for D in (-1e-2,-1e-3,-1e-4,-1e-5,-1e-6,-1e-7,-1e-8,-1e-9):
            om=1+D
            e=exact_far(True,om)+exact_far(False,om)
            a=approx_far(s,om)
            out.append(f"{D:.0e}:{(a-e).real:+.1e}")
        print(f"{taumax:.0e} xcf {xcf} n={sum(len(b[0]) for b in s)} time-err {err.max():.1e}", " ".join(out))
