// SpyPluginProbe: runs the real lcm-spy (lcm.spy.Spy from lcm.jar) in this JVM, double-clicks
// channels in its table the way a user does, and checks that lasonic's plugins open and follow
// the live messages. Used by tests/integration/spy_plugins_live.sh; needs a display (xvfb-run).
//
//   java -cp lcm.jar:jchart2d.jar:lcmtypes.jar:DIR SpyPluginProbe URL READY DONE CHANNELS DELAY_MS [PNG]
//
//  1. Starts lcm-spy (--lcm-url=URL), places its window at the top left, creates the file READY.
//  2. Waits (at most 60 s) until every channel of CHANNELS (comma-separated) is listed, then
//     double-clicks each one's row (a MouseEvent to lcm-spy's table: lcm-spy opens the first
//     plugin that handles the channel's type, else its own object viewer) and tiles the windows.
//  3. After DELAY_MS, and once every viewer has taken two messages or the replay has ended (DONE):
//     each channel must have a window holding a lasonic.spy.MapViewer that has taken at least two
//     messages (it follows the stream) and whose status is not an error;
//     prints "plugin CHANNEL ok|FAIL <viewer> <messages> <status>". With PNG: a screenshot of the
//     whole screen (java.awt.Robot) is written to PNG.
//  4. Waits (at most 120 s) for the file DONE, exits 0 if every channel passed, else 1.
import java.awt.Component;
import java.awt.Container;
import java.awt.Dimension;
import java.awt.Rectangle;
import java.awt.Robot;
import java.awt.Toolkit;
import java.awt.Window;
import java.awt.event.InputEvent;
import java.awt.event.MouseEvent;
import java.io.File;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.concurrent.atomic.AtomicReference;
import javax.imageio.ImageIO;
import javax.swing.JFrame;
import javax.swing.JInternalFrame;
import javax.swing.JTable;
import javax.swing.SwingUtilities;
import lasonic.spy.MapViewer;

public class SpyPluginProbe {
  static JTable findTable(Component c) {
    if (c instanceof JTable) return (JTable) c;
    if (c instanceof Container)
      for (Component k : ((Container) c).getComponents()) {
        JTable t = findTable(k);
        if (t != null) return t;
      }
    return null;
  }

  static MapViewer findViewer(Component c) {
    if (c instanceof MapViewer) return (MapViewer) c;
    if (c instanceof JInternalFrame) return null;  // lcm-spy's own viewer is not ours
    if (c instanceof Container)
      for (Component k : ((Container) c).getComponents()) {
        MapViewer v = findViewer(k);
        if (v != null) return v;
      }
    return null;
  }

  static JFrame spyFrame() {
    for (Window w : Window.getWindows())
      if (w instanceof JFrame && w.isShowing() && findTable(w) != null) return (JFrame) w;
    return null;
  }

  /** View row of the channel in lcm-spy's table, or -1. */
  static int rowOf(JTable t, String channel) {
    for (int r = 0; r < t.getRowCount(); r++)
      if (channel.equals(String.valueOf(t.getValueAt(r, 0)).trim())) return r;
    return -1;
  }

  public static void main(String[] args) throws Exception {
    if (args.length < 5) {
      System.err.println("usage: SpyPluginProbe URL READY DONE CHANNELS DELAY_MS [PNG]");
      System.exit(2);
    }
    final File ready = new File(args[1]), done = new File(args[2]);
    final List<String> channels = Arrays.asList(args[3].split(","));
    final long delay = Long.parseLong(args[4]);
    final String png = args.length > 5 ? args[5] : null;
    // Tiles on a 1280 x 800 screen: lcm-spy top left, then the plugins' windows.
    final Rectangle[] tiles = {new Rectangle(780, 0, 500, 400), new Rectangle(0, 400, 640, 400),
                               new Rectangle(640, 400, 640, 400), new Rectangle(0, 0, 780, 400)};

    lcm.spy.Spy.main(new String[] {"--lcm-url=" + args[0]});
    SwingUtilities.invokeAndWait(() -> {
      JFrame f = spyFrame();
      if (f != null) f.setBounds(0, 0, 780, 400);
    });
    if (!ready.createNewFile() && !ready.exists()) throw new RuntimeException("cannot create " + ready);

    // 2. Wait for the channels, then double-click each.
    long deadline = System.currentTimeMillis() + 60_000;
    while (true) {
      final AtomicReference<Boolean> all = new AtomicReference<>(false);
      SwingUtilities.invokeAndWait(() -> {
        JFrame f = spyFrame();
        JTable t = f == null ? null : findTable(f);
        boolean ok = t != null;
        for (String ch : channels) ok = ok && rowOf(t, ch) >= 0;
        all.set(ok);
      });
      if (all.get()) break;
      if (System.currentTimeMillis() > deadline) {
        System.err.println("SpyPluginProbe: lcm-spy did not list all of " + channels + " within 60 s");
        System.exit(1);
      }
      Thread.sleep(100);
    }
    final List<JFrame> opened = new ArrayList<>();
    for (int i = 0; i < channels.size(); i++) {
      final String ch = channels.get(i);
      final Rectangle tile = tiles[Math.min(i, tiles.length - 1)];
      SwingUtilities.invokeAndWait(() -> {
        List<Window> before = Arrays.asList(Window.getWindows());
        JTable t = findTable(spyFrame());
        Rectangle cell = t.getCellRect(rowOf(t, ch), 0, true);
        MouseEvent click = new MouseEvent(t, MouseEvent.MOUSE_CLICKED, System.currentTimeMillis(), InputEvent.BUTTON1_DOWN_MASK,
                                          cell.x + cell.width / 2, cell.y + cell.height / 2, 2, false, MouseEvent.BUTTON1);
        t.dispatchEvent(click);
        JFrame made = null;
        for (Window w : Window.getWindows())
          if (!before.contains(w) && w instanceof JFrame) made = (JFrame) w;
        if (made != null) made.setBounds(tile);
        opened.add(made);
      });
    }

    // 3. Let them follow the stream: DELAY_MS, then until every viewer has taken two messages or
    // the replay has ended (a loaded machine may open the windows late in the log).
    Thread.sleep(delay);
    long ended = -1;
    while (true) {
      final AtomicReference<Boolean> all = new AtomicReference<>(true);
      SwingUtilities.invokeAndWait(() -> {
        for (JFrame f : opened) {
          MapViewer v = f == null ? null : findViewer(f);
          if (v == null || v.messages() < 2) all.set(false);
        }
      });
      if (all.get()) break;
      if (ended < 0 && done.exists()) ended = System.currentTimeMillis();
      if (ended >= 0 && System.currentTimeMillis() - ended > 1000) break;
      if (System.currentTimeMillis() > deadline + 120_000) break;
      Thread.sleep(100);
    }
    int failed = 0;
    for (int i = 0; i < channels.size(); i++) {
      final JFrame f = opened.get(i);
      final AtomicReference<String> line = new AtomicReference<>();
      final AtomicReference<Boolean> ok = new AtomicReference<>(false);
      SwingUtilities.invokeAndWait(() -> {
        MapViewer v = f == null ? null : findViewer(f);
        if (v == null) {
          line.set(f == null ? "no window opened" : "the window holds no lasonic viewer (lcm-spy's own viewer?)");
          return;
        }
        String st = v.panel().status();
        boolean good = v.messages() >= 2 && !st.startsWith("invalid") && !st.startsWith("not a") && !st.startsWith("cannot")
                       && !st.startsWith("waiting");
        ok.set(good);
        line.set(v.getClass().getSimpleName() + " in \"" + f.getTitle() + "\" " + v.messages() + " messages: " + st);
      });
      System.out.println("plugin " + channels.get(i) + (ok.get() ? " ok " : " FAIL ") + line.get());
      if (!ok.get()) failed++;
    }
    if (png != null) {
      Dimension d = Toolkit.getDefaultToolkit().getScreenSize();
      ImageIO.write(new Robot().createScreenCapture(new Rectangle(0, 0, d.width, d.height)), "png", new File(png));
      System.out.println("screenshot " + png);
    }
    System.out.flush();

    // 4. The caller's replay ends.
    deadline = System.currentTimeMillis() + 120_000;
    while (!done.exists() && System.currentTimeMillis() < deadline) Thread.sleep(100);
    System.exit(failed == 0 ? 0 : 1);
  }
}
