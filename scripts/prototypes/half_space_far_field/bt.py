import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from es import *
def cauchy_chol(alpha,g):
    # P_ij = g_i conj(g_j)/(alpha_i + conj(alpha_j)), Re alpha>0. returns perm, L (n x n lower, P[perm][:,perm]=L L^*)
    n=len(alpha); alpha=alpha.astype(complex).copy(); g=g.astype(complex).copy()
    perm=np.arange(n); L=np.zeros((n,n),complex)
    gg=g.copy()
    for k in range(n):
        d=np.abs(gg[k:])**2/(2*alpha[k:].real)
        p=k+np.argmax(d)
        for arr in (alpha,gg,perm): arr[[k,p]]=arr[[p,k]]
        L[[k,p],:k]=L[[p,k],:k]
        dk=abs(gg[k])**2/(2*alpha[k].real)
        # column k of Schur complement: S_ik = gg_i conj(gg_k)/(alpha_i+conj(alpha_k))
        col=gg[k:]*np.conj(gg[k])/(alpha[k:]+np.conj(alpha[k]))
        L[k:,k]=col/np.sqrt(dk)
        # update generators
        gg[k+1:]=gg[k+1:]*(alpha[k+1:]-alpha[k])/(alpha[k+1:]+np.conj(alpha[k]))
    return perm,L
def bt(lam,a,tol):
    # system: x' = diag(lam) x + 1 u, y = sum a x ; returns reduced poles and residues
    alpha=-lam
    n=len(lam)
    pp,Lp=cauchy_chol(alpha,np.ones(n))
    Lpf=np.zeros((n,n),complex); Lpf[pp]=Lp       # P = Lpf Lpf^*
    # observability: Q_ij = conj(a_i) a_j / (conj(alpha_i)+alpha_j) -> conj-alpha Cauchy with g=conj(a)
    pq,Lq=cauchy_chol(np.conj(alpha),np.conj(a))
    Lqf=np.zeros((n,n),complex); Lqf[pq]=Lq       # Q = Lqf Lqf^*
    U,s,Vh=np.linalg.svd(Lqf.conj().T@Lpf)
    k=int(np.sum(s>tol))
    S=np.diag(s[:k]**-0.5)
    T=Lpf@Vh.conj().T[:,:k]@S
    Wt=S@U[:,:k].conj().T@Lqf.conj().T  # W^* 
    Ar=Wt@(lam[:,None]*T); br=Wt@np.ones(n); cr=a@T
    ev,X=np.linalg.eig(Ar)
    bb=np.linalg.solve(X,br); cc=cr@X
    return s,ev,cc*bb
if __name__=="__main__":
    tau0=1.0
    for taumax in (1e3,1e6,1e10):
        s=gl_sum(1.0,taumax,8)
        lam=np.concatenate([ -s[0][0]+1j, -s[1][0]+1j/r]); a=np.concatenate([s[0][1],s[1][1]])
        a=a*np.exp(lam*tau0)  # shift to start at tau0
        ref=gl_sum(0.5,1e14,16)
        tau=np.concatenate([np.linspace(1,50,2000),np.logspace(1.7,np.log10(taumax),3000),np.logspace(np.log10(taumax),np.log10(taumax)+1,100)])
        gref=2*np.real(np.exp(np.outer(tau,-ref[0][0]+1j))@ref[0][1]+np.exp(np.outer(tau,-ref[1][0]+1j/r))@ref[1][1])
        for tol in (1e-9,1e-10,1e-11,1e-12):
            sv,ev,res=bt(lam,a,tol)
            g=2*np.real(np.exp(np.outer(tau-tau0,ev))@res)
            m=tau<=taumax
            print(f"taumax {taumax:.0e} tol {tol:.0e}: {len(ev)} of {len(lam)}; maxerr {np.abs(g-gref)[m].max():.2e}, beyond {np.abs(g-gref)[~m].max():.1e}; max Re ev {ev.real.max():.2e} min {ev.real.min():.2e}")
        print("  sv:", " ".join(f"{x:.1e}" for x in sv[::6]))
