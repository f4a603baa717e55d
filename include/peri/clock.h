/* Wall-clock time for progress lines and timings. */
#ifndef PERI_CLOCK_H
#define PERI_CLOCK_H

/* Seconds on the monotonic clock (unaffected by changes of the system time); only
 * differences are meaningful. */
double peri_seconds(void);

#endif
