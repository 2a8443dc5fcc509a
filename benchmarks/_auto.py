"""The parts of the AUTO-07p equations files (Fortran 90) that the benchmarks against AUTO
(``bench_branch.py``, ``bench_diagram.py``) share: the declarations opening ``FUNC`` and
``STPNT``, and the subroutines AUTO asks for that these problems leave empty."""

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
