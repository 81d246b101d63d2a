import numpy as np
nu=0.33
# plane strain: cd^2/cs^2 = 2(1-nu)/(1-2nu)
r2=(1-2*nu)/(2*(1-nu)); r=np.sqrt(r2)
def on_cut(shear,x,side):
    b=1.0 if shear else 1/r
    zeta=-x+1j*b
    oc=side*1j*np.sqrt(x)
    i=1j
    if shear:
        a_s=oc*np.sqrt(zeta+i); a_d=r*np.sqrt(zeta-i/r)*np.sqrt(zeta+i/r)
    else:
        a_s=np.sqrt(zeta-i)*np.sqrt(zeta+i); a_d=r*oc*np.sqrt(zeta+i/r)
    return 2*(1-r2)/(zeta*(a_s+a_d))+zeta/(2*a_s)-0.5
def density(shear,x):
    return -(on_cut(shear,x,1)-on_cut(shear,x,-1))/(2j*np.pi)
def gl_sum(tau_min,tau_max,npp,ratio=2.0):
    u_min=1/np.sqrt(tau_max); u_max=np.sqrt(36/tau_min)
    e=[0,u_min]
    while e[-1]<u_max: e.append(ratio*e[-1])
    xg,wg=np.polynomial.legendre.leggauss(npp)
    out=[]
    for shear in (True,False):
        xs=[];ws=[]
        for a,c in zip(e[:-1],e[1:]):
            u=0.5*(c-a)*xg+0.5*(c+a); w=0.5*(c-a)*wg
            xs.append(u*u); ws.append(w*2*u*density(shear,u*u))
        out.append((np.concatenate(xs),np.concatenate(ws)))
    return out  # per branch (x nodes, complex weights)
def envelope(br,tau):
    x,w=br
    return np.exp(-np.outer(tau,x))@w
