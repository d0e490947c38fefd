# A side task dies while the main task carries on, nobody awaiting it: on a board the
# default handler prints it and the robot drives on without that task.
import asyncio


async def sensor_task():
    await asyncio.sleep_ms(120)
    raise ValueError("sensor task died")


async def main():
    asyncio.create_task(sensor_task())
    while True:
        await asyncio.sleep_ms(50)


asyncio.run(main())
