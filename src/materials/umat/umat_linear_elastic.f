C     Linear elastic, isotropic, hypoelastic: the example UMAT of dpmpm in fixed form
C     (doc/input.md, "A user's UMAT"). The stress it is given is already rotated with
C     the spin, so that adding D : DSTRAN makes the Jaumann-rate model of dpmpm's
C     'linear_elastic' (tests/test_umat_elastic.f90 compares them).
C     PROPS(1) = E (Pa), PROPS(2) = nu. No state variables (NSTATV = 0).
C     DDSDDE = D: lambda on the normal block, plus 2 mu on its diagonal, mu for the
C     engineering shears. SSE = sigma : D^-1 : sigma / 2, the elastic energy per volume.
      SUBROUTINE UMAT(STRESS,STATEV,DDSDDE,SSE,SPD,SCD,
     1 RPL,DDSDDT,DRPLDE,DRPLDT,
     2 STRAN,DSTRAN,TIME,DTIME,TEMP,DTEMP,PREDEF,DPRED,CMNAME,
     3 NDI,NSHR,NTENS,NSTATV,PROPS,NPROPS,COORDS,DROT,PNEWDT,
     4 CELENT,DFGRD0,DFGRD1,NOEL,NPT,LAYER,KSPT,JSTEP,KINC)
C
      INCLUDE 'ABA_PARAM.INC'
C
      CHARACTER*80 CMNAME
      DIMENSION STRESS(NTENS),STATEV(*),DDSDDE(NTENS,NTENS),
     1 DDSDDT(NTENS),DRPLDE(NTENS),STRAN(NTENS),DSTRAN(NTENS),
     2 TIME(2),PREDEF(1),DPRED(1),PROPS(NPROPS),COORDS(3),DROT(3,3),
     3 DFGRD0(3,3),DFGRD1(3,3),JSTEP(4)
C
      YOUNG = PROPS(1)
      ANU = PROPS(2)
      ALAMB = YOUNG*ANU/((1.0D0 + ANU)*(1.0D0 - 2.0D0*ANU))
      SHEAR = YOUNG/(2.0D0*(1.0D0 + ANU))
C
      DO 20 I = 1, NTENS
        DO 10 J = 1, NTENS
          DDSDDE(I, J) = 0.0D0
   10   CONTINUE
   20 CONTINUE
      DO 40 I = 1, NDI
        DO 30 J = 1, NDI
          DDSDDE(I, J) = ALAMB
   30   CONTINUE
        DDSDDE(I, I) = ALAMB + 2.0D0*SHEAR
   40 CONTINUE
      DO 50 I = NDI + 1, NTENS
        DDSDDE(I, I) = SHEAR
   50 CONTINUE
C
C     the trial is exact for a linear model: sigma + D : DSTRAN
      TRACE = 0.0D0
      DO 60 I = 1, NDI
        TRACE = TRACE + DSTRAN(I)
   60 CONTINUE
      DO 70 I = 1, NDI
        STRESS(I) = STRESS(I) + (ALAMB*TRACE + 2.0D0*SHEAR*DSTRAN(I))
   70 CONTINUE
      DO 80 I = NDI + 1, NTENS
        STRESS(I) = STRESS(I) + SHEAR*DSTRAN(I)
   80 CONTINUE
C
C     the stored energy per volume at the new stress
      SNORM = 0.0D0
      SSHEAR = 0.0D0
      STRACE = 0.0D0
      DO 90 I = 1, NDI
        SNORM = SNORM + STRESS(I)**2
        STRACE = STRACE + STRESS(I)
   90 CONTINUE
      DO 100 I = NDI + 1, NTENS
        SSHEAR = SSHEAR + STRESS(I)**2
  100 CONTINUE
      SSE = 0.5D0*((1.0D0 + ANU)*(SNORM + 2.0D0*SSHEAR)
     1      - ANU*STRACE**2)/YOUNG
      RETURN
      END
