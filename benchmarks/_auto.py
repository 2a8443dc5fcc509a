"""The parts of the AUTO-07p equations files (Fortran 90) that the benchmarks against AUTO
(``bench_branch.py``, ``bench_diagram.py``) share: the declarations opening ``FUNC`` and
``STPNT``, the subroutines AUTO asks for that these problems leave empty, and the SEDF at
rest with a gain (:func:`sedf_equations`, :func:`sedf_constants`)."""

import textwrap

#: the head of ``SUBROUTINE FUNC``: its arguments declared
FUNC_HEAD = """\
SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
"""

#: the head of ``SUBROUTINE STPNT``: its arguments declared
STPNT_HEAD = """\
SUBROUTINE STPNT(NDIM,U,PAR,T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
"""

#: the empty ``BCND``, ``ICND``, ``FOPT`` and ``PVLS``
EMPTY_SUBROUTINES = "".join(f"SUBROUTINE {name}\nEND SUBROUTINE {name}\n"
                            for name in ("BCND", "ICND", "FOPT", "PVLS"))


def sedf_equations(beta: str) -> str:
    """The SEDF at rest with a gain ``s`` (paper eq. 3, ``x'' + mu (beta x^2 - s) x' +
    Delta sin(2 pi x/lam) + x = 0``), ``PAR = (Delta, s, mu, beta, lam)``, with its
    Jacobians (used where the constants say ``JAC = 1``), from rest at ``Delta = 0``, ``s =
    -0.1``, ``mu = 0.1``, ``lam = 1`` and ``beta`` (a Fortran literal, e.g. ``"1.0D0"``)."""
    return "!  the SEDF at rest with a gain s: PAR = (Delta, s, mu, beta, lam)\n" \
        + FUNC_HEAD + textwrap.dedent("""\
      DOUBLE PRECISION PI, K
      PI = 4.0D0*ATAN(1.0D0)
      K = 2*PI/PAR(5)
      F(1) = U(2)
      F(2) = -U(1) - PAR(3)*(PAR(4)*U(1)*U(1) - PAR(2))*U(2) - PAR(1)*SIN(K*U(1))
      IF (IJAC == 0) RETURN
      DFDU(1, 1) = 0.0D0
      DFDU(1, 2) = 1.0D0
      DFDU(2, 1) = -1.0D0 - 2*PAR(3)*PAR(4)*U(1)*U(2) - PAR(1)*K*COS(K*U(1))
      DFDU(2, 2) = -PAR(3)*(PAR(4)*U(1)*U(1) - PAR(2))
      IF (IJAC /= 2) RETURN
      DFDP(1, 1:5) = 0.0D0
      DFDP(2, 1) = -SIN(K*U(1))
      DFDP(2, 2) = PAR(3)*U(2)
      DFDP(2, 3) = -(PAR(4)*U(1)*U(1) - PAR(2))*U(2)
      DFDP(2, 4) = -PAR(3)*U(1)*U(1)*U(2)
      DFDP(2, 5) = PAR(1)*COS(K*U(1))*K*U(1)/PAR(5)
    END SUBROUTINE FUNC

""") + STPNT_HEAD + textwrap.dedent(f"""\
      PAR(1) = 0.0D0
      PAR(2) = -0.1D0
      PAR(3) = 0.1D0
      PAR(4) = {beta}
      PAR(5) = 1.0D0
      U(1) = 0.0D0
      U(2) = 0.0D0
    END SUBROUTINE STPNT

""") + EMPTY_SUBROUTINES


def sedf_constants(npr: int, itnw: int, nwtn: int, jac: int) -> str:
    """AUTO's constants file ``c.sedf`` of :func:`sedf_equations`: the Hopf point of the
    origin continued in the gain ``s`` (NTST = 200, NCOL = 4, EPSL = EPSU = 1e-7, EPSS =
    1e-9), with the print interval ``NPR``, Newton's steps ``ITNW``, ``NWTN`` and ``JAC``
    as given."""
    return textwrap.dedent(f"""\
    parnames = {{1: 'Delta', 2: 's', 3: 'mu', 4: 'beta', 5: 'lam'}}
    NDIM=   2, IPS =   1, IRS =   0, ILP =   1
    ICP =  ['s']
    NTST=  200, NCOL=   4, IAD =   3, ISP =   2, ISW = 1, IPLT= 0, NBC= 0, NINT= 0
    NMX=  300, NPR=  {npr}, MXBF=  10, IID =   2, ITMX= 8, ITNW= {itnw}, NWTN= {nwtn}, JAC= {jac}
    EPSL= 1e-07, EPSU = 1e-07, EPSS =1e-09
    DS  =   0.01, DSMIN=  1e-05, DSMAX=   0.05, IADS=   1
    NPAR = 11, THL =  {{11: 0.0}}, THU =  {{}}
    UZSTOP = {{'s': 0.5}}
    """)
