import math, sys
# 1-D prototype of mpm-snow's column (docs/mpm.md, `mpm-snow`, 2026-12-06): quadratic
# B-splines, APIC, a slip floor (folded image), the sticky plate (image + fold, as
# chrono_mpm::rigid), one marker per cell. Reproduces the engine's lag and J spread.
# python3 docs/mpm-snow-1d.py QUAD CELLS ELASTIC FINAL_STRAIN [PLATE [dens|x [STEP]]]
#   QUAD: point (the engine's), domain (cpGIMP gradient: (N(x+l) - N(x-l))/2l for the
#         stress and grad v, point weights for the transfers), full (domain weights too)
#   ELASTIC: 1 for fixed-corotated without plasticity
#   PLATE: image (the engine's), node (v = v_b inside), traction (no plate: the exact
#          stress history on the top surface), mirror (mirrored virtual markers about the
#          plate's surface, no node condition), mirror_image (mirrored markers for the
#          nodes outside, the image on the nodes inside, no fold; chrono_mpm's
#          RigidBody::mirrored_markers), mirror_fold (the mirrored markers' mass and
#          momentum without their stress; the real markers' stress on the image nodes
#          folded by the image's transpose, -w_k f_g, onto the nodes it reads); the mirror modes
#          report the markers' mean stress (quasi-static) against the curve at the strain
#   STEP: the sampling interval of the strain (0.025)
#   dens: the plastic branch's J_P from the grid's density (mirrored markers)
# Prints per 2.5 % strain: sum J d0 - plate (the lag, dx), the J range, and the plate's
# mean stress over the interval against the exact curve at its middle strain.
def N(r):
    a=abs(r)
    return 0.75-a*a if a<0.5 else (0.5*(1.5-a)**2 if a<1.5 else 0.0)
def dN(r):
    a=abs(r)
    return -2*r if a<0.5 else ((-(1.5-a) if r>0 else (1.5-a)) if a<1.5 else 0.0)
def run(quad, cells=8, ppc=1, elastic=False, strain_end=0.3, rate=0.1):
    H=0.1; dx=H/cells; E=1.4e5; nu=0.2; rho=400.0; tc=2.5e-2; ts=7.5e-3; xi=10.0
    mu=E/(2*(1+nu)); lam=E*nu/((1+nu)*(1-2*nu)); M=lam+2*mu
    n=cells*ppc; d0=H/n
    x=[(k+0.5)*d0 for k in range(n)]; v=[0.0]*n; C=[0.0]*n; s=[1.0]*n; jp=[1.0]*n
    m=rho*d0; V0=d0
    zb=H; t=0.0; tr=0.05; imp=0.0; out=[]; nxt=0.025; t0=0; s0=0.0; i0=0.0
    def stress_exact(st):
        S=1-st
        if elastic or S>=1-tc: return M*(S-1)*S/S  # cauchy = tau/J, tau=M(s-1)s
        J=S/(1-tc); return math.exp(xi*(1-J))*M*(-tc)/J
    sum_vb_t=[0.0]
    while True:
        strain=(H-zb)/H if PLATE!='traction' else -sum_vb_t[0]/H
        if strain>=strain_end: break
        vb=-rate*H*(0.5*(1-math.cos(math.pi*t/tr)) if t<tr else 1.0)
        h=[1.0 if elastic else math.exp(xi*(1-j)) for j in jp]
        c=max(math.sqrt(M*hh/rho)+abs(vv) for hh,vv in zip(h,v))
        dt=0.999*0.4*dx/c
        K=cells+4
        def wts(p):
            g=x[p]/dx; b=math.floor(g-0.5)
            if quad!='full': return [(i,N(g-i)) for i in range(b,b+3)]
            l=0.5*d0*s[p]*jp[p]; q=32
            lo=math.floor((x[p]-l)/dx-0.5); hi=math.floor((x[p]+l)/dx-0.5)+2
            return [(i,sum(N((x[p]-l+(k+0.5)*2*l/q)/dx-i) for k in range(q))/q) for i in range(lo,hi+1)]
        mass={}; mom={}; frc={}
        tau=[M*h[p]*(s[p]-1)*s[p] for p in range(n)]
        for p in range(n):
            g=x[p]/dx; b=math.floor(g-0.5)
            for i,w in wts(p):
                mass[i]=mass.get(i,0)+w*m
                mom[i]=mom.get(i,0)+w*m*(v[p]+C[p]*(i*dx-x[p]))
            if quad=='point':
                for i in range(b,b+3):
                    mom[i]=mom.get(i,0)-dt*V0*tau[p]*dN(g-i)/dx
                    frc[i]=frc.get(i,0)-dt*V0*tau[p]*dN(g-i)/dx
            else:
                l=0.5*d0*s[p]*jp[p]
                lo=math.floor((x[p]-l)/dx-0.5); hi=math.floor((x[p]+l)/dx-0.5)+2
                for i in range(lo,hi+1):
                    G=(N((x[p]+l)/dx-i)-N((x[p]-l)/dx-i))/(2*l)
                    mom[i]=mom.get(i,0)-dt*V0*tau[p]*G
        if PLATE=='traction':
            # prescribed stress history on the top surface, instead of the plate
            eps=min(-sum_vb_t[0]/H, 0.999)
            sig_t=-stress_exact(eps)  # compressive magnitude
            ztop=x[-1]+0.5*d0*s[-1]*jp[-1]
            g=ztop/dx; b=math.floor(g-0.5)
            for i in range(b,b+3):
                mom[i]=mom.get(i,0)-dt*sig_t*N(g-i)
        if PLATE in ('mirror','mirror_image','mirror_fold'):
            for p in range(n):
                xv=2*zb-x[p]; vv=2*vb-v[p]
                g=xv/dx; b=math.floor(g-0.5)
                for i in range(b,b+3):
                    w=N(g-i)
                    mass[i]=mass.get(i,0)+w*m
                    mom[i]=mom.get(i,0)+w*m*(vv+C[p]*(i*dx-xv))-(dt*V0*tau[p]*dN(g-i)/dx if PLATE!='mirror_fold' else 0.0)
        # floor: fold ghosts -1,-2 into 1,2 (slip: normal component odd)
        for gi in (-1,-2):
            if gi in mass and mass[gi]>0:
                mass[-gi]=mass.get(-gi,0)+mass[gi]; mom[-gi]=mom.get(-gi,0)-mom[gi]
        if PLATE=='mirror_fold':
            # the real stress on the image nodes, folded by the image's transpose
            k_=math.floor(zb/dx-1e-12)
            if abs(k_*dx-zb)<1e-12: k_-=1
            for gi in [i for i in sorted(mass) if i*dx>=zb and mass[i]>0 and i>0]:
                a=gi*dx-zb; zm=zb-a
                if gi*dx==zb: L=[]
                elif zm>=k_*dx: L=[(k_,(zb-zm)/(zb-k_*dx))]
                else:
                    u=(k_*dx-zm)/dx; L=[(k_,1-u),(k_-1,u)]
                for kk,w in L:
                    mom[kk]=mom.get(kk,0)-w*frc.get(gi,0)
        vel={i:(mom[i]/mass[i] if mass[i]>0 else 0.0) for i in mass}
        vel[0]=0.0
        # plate: nodes with z_i >= zb and mass are ghosts; image from the surface and the top free node
        k=math.floor(zb/dx-1e-12)  # highest node strictly below zb
        if abs(k*dx-zb)<1e-12: k-=1
        ghosts=[i for i in sorted(mass) if i*dx>=zb and mass[i]>0 and i>0] if PLATE in ('image','node','mirror_image','mirror_fold') else []
        before={i:vel[i] for i in vel}
        # links
        folds={}
        def link(i):
            a=i*dx-zb; zm=zb-a
            if zm>=k*dx:
                tt=(zb-zm)/(zb-k*dx); return [(k,tt)]
            # between k-1 and k, from the surface: v(zm)=lin interp nodes k-1,k
            u=(k*dx-zm)/dx
            return [(k,1-u),(k-1,u)]  # weights of (v-vb) ; image v_g=vb - sum w (v_k - vb)... approx
        for gi in ghosts:
            L=link(gi)
            if gi*dx==zb: L=[]
            e=(vel[gi]-vb)+sum(w*(vel[kk]-vb) for kk,w in L)
            W=sum(w for _,w in L)
            for kk,w in L:
                folds.setdefault(kk,[0.0,0.0]); folds[kk][0]+=w*W*mass[gi]; folds[kk][1]+=-w*mass[gi]*e
        J=0.0
        if PLATE in ('node','mirror_image','mirror_fold'): folds={}
        for kk,(dm,dp) in folds.items():
            if kk<=0: continue
            nv=vel[kk]+dp/(mass[kk]+dm); J+=mass[kk]*(nv-vel[kk]); vel[kk]=nv
        for gi in ghosts:
            L=link(gi)
            nv=vb-sum(w*(vel[kk]-vb) for kk,w in L) if gi*dx!=zb else vb
            if PLATE=='node': nv=vb
            J+=mass[gi]*(nv-vel[gi]); vel[gi]=nv
        # floor ghost images
        for gi in (-1,-2):
            if gi in vel: vel[gi]=-vel.get(-gi,0.0)
        imp+=J
        # density at the markers from the nodes' masses with mirrored markers (floor, plate)
        if DENS:
            mm={}
            for p in range(n):
                for xx in (x[p], -x[p], 2*zb-x[p]):
                    g=xx/dx; b=math.floor(g-0.5)
                    for i in range(b,b+3):
                        mm[i]=mm.get(i,0)+N(g-i)*m
            jg=[]
            for p in range(n):
                g=x[p]/dx; b=math.floor(g-0.5)
                rho_p=sum(N(g-i)*mm.get(i,0) for i in range(b,b+3))/dx
                jg.append(rho/rho_p)
        # G2P
        for p in range(n):
            g=x[p]/dx; b=math.floor(g-0.5)
            vp=0; B=0; gv=0
            for i,w in wts(p):
                vi=vel.get(i,0.0)
                vp+=w*vi; B+=w*vi*(i*dx-x[p])
            if quad=='point':
              for i in range(b,b+3): gv+=vel.get(i,0.0)*dN(g-i)/dx
            if quad!='point':
                l=0.5*d0*s[p]*jp[p]
                lo=math.floor((x[p]-l)/dx-0.5); hi=math.floor((x[p]+l)/dx-0.5)+2
                for i in range(lo,hi+1):
                    gv+=vel.get(i,0.0)*(N((x[p]+l)/dx-i)-N((x[p]-l)/dx-i))/(2*l)
            v[p]=vp; C[p]=B*4/dx/dx
            st=s[p]*(1+dt*gv)
            if not elastic:
                if st<1-tc:
                    jp[p]*=st/(1-tc); st=1-tc
                    if DENS: jp[p]=jg[p]/st
                elif st>1+ts: jp[p]*=st/(1+ts); st=1+ts
            s[p]=st
            x[p]+=dt*vp
        zb+=vb*dt; t+=dt; sum_vb_t[0]+=vb*dt
        if PLATE=='traction': zb=x[-1]+0.5*d0*s[-1]*jp[-1]
        if strain>=nxt:
            sig=-(imp-i0)/(t-t0)
            smid=0.5*(strain+s0); s0=strain; t0=t; i0=imp; nxt+=STEP
            Js=[s[p]*jp[p] for p in range(n)]
            if PLATE in ('mirror','mirror_image','mirror_fold'):
                sig=-sum(V0*tt for tt in tau)/zb  # the markers' mean axial stress
            print('%s strain %.3f  sum J d0 - zb = %+.3f dx  J spread %.4f..%.4f  (unif %.4f) plate stress/exact at mid %.4f'%(quad,strain,(sum(Js)*d0-zb)/dx,min(Js),max(Js),1-strain,sig/-stress_exact(smid if PLATE not in ('mirror','mirror_image','mirror_fold') else strain)))
            print('   top marker: plate - x_top = %.3f dx, J range in the lower half %.4f..%.4f'%((zb-x[-1])/dx, min(Js[:n//2]), max(Js[:n//2])))
            sys.stdout.flush()
DENS=len(sys.argv)>6 and sys.argv[6]=='dens'
STEP=float(sys.argv[7]) if len(sys.argv)>7 else 0.025
PLATE=sys.argv[5] if len(sys.argv)>5 else 'image'
quad=sys.argv[1]; cells=int(sys.argv[2]); el=sys.argv[3]=='1'
run(quad,cells=cells,elastic=el,strain_end=float(sys.argv[4]) if len(sys.argv)>4 else 0.3)
